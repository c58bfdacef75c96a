// What a process turned away of what it received: the intake checks'
// verdicts (core/intake.hpp) counted - dropped as malformed, refused as
// implausible by reason - and the first few of each logged, so that a flood
// of hostile samples does not flood the log.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "pheromesh/core/intake.hpp"
#include "pheromesh/core/plausibility.hpp"

namespace spdlog {
class logger;
}

namespace pheromesh::runtime {

class SampleAudit {
 public:
  explicit SampleAudit(std::shared_ptr<spdlog::logger> log) : log_(std::move(log)) {}
  // True if `v` takes the sample; otherwise counts and (the first few) logs it.
  bool admit(const core::IntakeVerdict& v);
  // A refusal decided elsewhere (e.g. a clock sample of another writer), of
  // `samples` samples at once (0: nothing).
  void refuse(core::Refusal r, const std::string& what, std::size_t samples = 1);
  void drop(const std::string& what);

  [[nodiscard]] uint64_t dropped() const { return dropped_; }
  [[nodiscard]] const core::RefusalCounts& refused() const { return refused_; }

  static constexpr uint64_t kDropsLogged = 3;
  static constexpr uint64_t kRefusalsLogged = 5;

 private:
  std::shared_ptr<spdlog::logger> log_;
  uint64_t dropped_ = 0;
  core::RefusalCounts refused_;
};

}  // namespace pheromesh::runtime
