// Target marks and the revisit timer, Shao 2020 Algorithm 1 (revisit every T).
#include "pheromesh/core/marks.hpp"

#include <algorithm>

namespace pheromesh::core {

std::optional<MarkEvent> TargetMarks::mark(Cell c, uint32_t tick) {
  const auto it = marks_.find(key(c));
  if (it == marks_.end()) {
    marks_.emplace(key(c), State{c, tick, false});
    return MarkEvent{MarkEvent::Kind::FirstMarked, c, tick, 0};
  }
  State& s = it->second;
  if (!s.due) {
    return std::nullopt;  // marked, revisit not yet due: nothing changes
  }
  // A tick earlier than the due tick (out-of-order sample) counts as 0 ticks.
  const uint32_t response = tick >= s.since ? tick - s.since : 0;
  s.due = false;
  s.since = tick;
  return MarkEvent{MarkEvent::Kind::Revisited, c, tick, response};
}

std::vector<MarkEvent> TargetMarks::advance(uint32_t tick) {
  std::vector<MarkEvent> events;
  for (auto& [k, s] : marks_) {
    if (!s.due && tick >= s.since && tick - s.since >= period_) {
      s.due = true;
      s.since = tick;  // from now on `since` is the tick the revisit became due
      events.push_back(MarkEvent{MarkEvent::Kind::RevisitDue, s.cell, tick, 0});
    }
  }
  // The map's iteration order is unspecified; report in (y, x) order.
  std::sort(events.begin(), events.end(), [](const MarkEvent& a, const MarkEvent& b) {
    return a.cell.y != b.cell.y ? a.cell.y < b.cell.y : a.cell.x < b.cell.x;
  });
  return events;
}

bool TargetMarks::due(Cell c) const {
  const auto it = marks_.find(key(c));
  return it != marks_.end() && it->second.due;
}

bool TargetMarks::marked(Cell c) const { return marks_.find(key(c)) != marks_.end(); }

}  // namespace pheromesh::core
