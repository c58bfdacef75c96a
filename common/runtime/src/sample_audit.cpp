#include "pheromesh/runtime/sample_audit.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdint>

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

void SampleAudit::refuse(core::Refusal r, const std::string& what, std::size_t samples) {
  if (samples == 0) return;
  const bool logged = refused_.total() < kRefusalsLogged;
  refused_.add(r, static_cast<uint32_t>(std::min<std::size_t>(samples, UINT32_MAX)));
  if (logged) log_->warn("refused {} ({})", what, core::refusal_name(r));
}

void SampleAudit::drop(const std::string& what) {
  if (++dropped_ <= kDropsLogged) log_->warn("dropped {}", what);
}

}  // namespace pheromesh::runtime
