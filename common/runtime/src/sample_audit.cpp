#include "pheromesh/runtime/sample_audit.hpp"

#include <spdlog/spdlog.h>

namespace pheromesh::runtime {

bool SampleAudit::admit(const core::IntakeVerdict& v) {
  switch (v.kind) {
    case core::IntakeVerdict::Kind::Take:
      return true;
    case core::IntakeVerdict::Kind::Drop:
      drop(v.reason);
      return false;
    case core::IntakeVerdict::Kind::Refuse:
      refuse(v.refusal, v.reason);
      return false;
  }
  return false;
}

void SampleAudit::refuse(core::Refusal r, const std::string& what) {
  refused_.add(r);
  if (refused_.total() <= kRefusalsLogged) log_->warn("refused {} ({})", what, core::refusal_name(r));
}

void SampleAudit::drop(const std::string& what) {
  if (++dropped_ <= kDropsLogged) log_->warn("dropped {}", what);
}

}  // namespace pheromesh::runtime
