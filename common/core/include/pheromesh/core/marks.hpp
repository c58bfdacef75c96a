// Target marks and the revisit timer (Shao 2020 Algorithm 1 and the kτ switch
// of Shao 2020 eq. (1)), kept by the place agent that owns the target's cell.
#pragma once

#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "pheromesh/core/grid.hpp"

namespace pheromesh::core {

struct MarkEvent {
  enum class Kind : uint8_t { FirstMarked = 0, RevisitDue = 1, Revisited = 2 };
  Kind kind = Kind::FirstMarked;
  Cell cell{};
  uint32_t tick = 0;
  uint32_t response_ticks = 0;  // Revisited: ticks from RevisitDue to this mark
};

class TargetMarks {
 public:
  explicit TargetMarks(uint32_t revisit_period) : period_(revisit_period) {}
  // A UAV marks the target at c at tick t. Unknown -> marked (timer starts);
  // due -> marked again (timer restarts, response time reported); marked -> no change.
  std::optional<MarkEvent> mark(Cell c, uint32_t tick);
  // Advances timers to tick t; returns targets that became due.
  std::vector<MarkEvent> advance(uint32_t tick);
  [[nodiscard]] bool due(Cell c) const;
  [[nodiscard]] bool marked(Cell c) const;

 private:
  struct State {
    Cell cell;
    uint32_t since = 0;  // tick of last mark, or of becoming due
    bool due = false;
  };
  uint32_t period_;
  std::unordered_map<uint64_t, State> marks_;
  static uint64_t key(Cell c) { return (static_cast<uint64_t>(static_cast<uint32_t>(c.x)) << 32) | static_cast<uint32_t>(c.y); }
};

}  // namespace pheromesh::core
