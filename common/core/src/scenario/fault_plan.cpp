#include "pheromesh/core/fault_plan.hpp"

#include <algorithm>
#include <stdexcept>

namespace pheromesh::core {

FaultPlan::FaultPlan(FaultSchedule schedule) : schedule_(std::move(schedule)), state_(schedule_.events.size()) {}

bool FaultPlan::has_end(FaultAction a) {
  return a == FaultAction::Stop || a == FaultAction::Partition || a == FaultAction::Loss || a == FaultAction::Restart;
}

std::vector<std::size_t> FaultPlan::take_due_at(double now_s) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < state_.size(); ++i) {
    const FaultEvent& e = schedule_.events[i];
    if (state_[i].taken || !e.at_s || *e.at_s > now_s) continue;
    state_[i].taken = true;
    out.push_back(i);
  }
  return out;
}

std::vector<std::size_t> FaultPlan::take_due_before_tick(uint32_t tick) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < state_.size(); ++i) {
    const FaultEvent& e = schedule_.events[i];
    if (state_[i].taken || !e.at_tick || *e.at_tick > tick) continue;
    state_[i].taken = true;
    out.push_back(i);
  }
  return out;
}

void FaultPlan::begin(std::size_t i, double now_s, std::vector<std::string> targets, std::optional<uint32_t> tick,
                      std::string note) {
  State& st = state_.at(i);
  if (st.record) throw std::logic_error("fault event " + std::to_string(i) + " begun twice");
  st.taken = true;
  const FaultEvent& e = schedule_.events[i];
  FaultRecord r;
  r.event = i;
  r.action = e.action;
  r.targets = std::move(targets);
  r.at_s = now_s;
  r.tick = tick;
  r.duration_s = e.duration_s;
  r.note = std::move(note);
  if (has_end(e.action)) {
    st.end_at_s = now_s + e.duration_s;
  } else {
    r.done_at_s = now_s;
  }
  st.record = records_.size();
  records_.push_back(std::move(r));
}

std::vector<std::size_t> FaultPlan::take_ends_at(double now_s) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < state_.size(); ++i) {
    if (state_[i].end_at_s && *state_[i].end_at_s <= now_s) {
      state_[i].end_at_s.reset();
      out.push_back(i);
    }
  }
  // Earliest end first: a restart that ends before a partition ends is started
  // again while it is still cut off, as the schedule says.
  std::stable_sort(out.begin(), out.end(), [this](std::size_t a, std::size_t b) {
    return records_[*state_[a].record].at_s + schedule_.events[a].duration_s <
           records_[*state_[b].record].at_s + schedule_.events[b].duration_s;
  });
  return out;
}

std::vector<std::size_t> FaultPlan::take_all_ends() {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < state_.size(); ++i) {
    if (state_[i].end_at_s) {
      state_[i].end_at_s.reset();
      out.push_back(i);
    }
  }
  return out;
}

void FaultPlan::end(std::size_t i, double now_s, const std::string& note) {
  const State& st = state_.at(i);
  if (!st.record) throw std::logic_error("fault event " + std::to_string(i) + " ended before it began");
  FaultRecord& r = records_[*st.record];
  r.done_at_s = now_s;
  if (!note.empty()) r.note = r.note.empty() ? note : r.note + "; " + note;
}

std::vector<uint32_t> FaultPlan::fault_ticks() const {
  std::vector<uint32_t> ticks;
  for (const auto& e : schedule_.events) {
    if (e.at_tick) ticks.push_back(*e.at_tick);
  }
  std::sort(ticks.begin(), ticks.end());
  ticks.erase(std::unique(ticks.begin(), ticks.end()), ticks.end());
  return ticks;
}

bool FaultPlan::all_taken() const {
  return std::all_of(state_.begin(), state_.end(), [](const State& s) { return s.taken; });
}

}  // namespace pheromesh::core
