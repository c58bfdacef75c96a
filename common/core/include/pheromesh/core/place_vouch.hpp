// Which processes are place agents, as one receiver heard them (issue 28,
// docs/architecture.md "What a receiver refuses"). On an open domain any
// process can write any topic; what a forger cannot copy is its process,
// which the receiving bus names (the DDS participant,
// bus::SampleInfo::participant, the same on every vendor).
//
// What only place agent `id` (core::place_id: region and replica) writes -
// its health to the ground station, its served UAVs to the other place
// agents - latches `id` to the process that wrote it first (as the UAV
// state latch does per UAV, writer_latch.hpp). What a place agent relays or
// forwards for others - UAV states, detections, broadcasts, tiles and
// fields to the ground station, deposits to the region they are for - is
// taken only from a process that holds some place id. A process heard
// before it holds one (a place agent started again, whose dead process
// holds its id until silent for the takeover time) is not refused at once:
// its samples wait (Parked) up to park_for() and are refused only then.
// Pure, no I/O.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

#include "pheromesh/core/writer_latch.hpp"

namespace pheromesh::core {

class PlaceVouch {
 public:
  using Clock = std::chrono::steady_clock;
  // A later life of a place agent (PlaceHealth.life, given by the launcher
  // that started it again) takes its id from a holder silent this long: a
  // process killed and started again is silent for longer than that.
  static constexpr Clock::duration kNewLifeSilence = std::chrono::seconds(1);

  // `takeover_after`: a place id whose process wrote nothing for this long
  // goes to the next process heard for it.
  explicit PlaceVouch(Clock::duration takeover_after) : latch_(takeover_after), takeover_after_(takeover_after) {}

  // A sample only place `id` writes came from `participant`. True if it may
  // write as `id`: it holds it, the id is free, its holder was silent for the
  // takeover time, or (`new_life`) the sample is of a later life and the
  // holder was silent for kNewLifeSilence. It then holds `id`. Participant 0
  // (a transport that cannot tell) may always and holds nothing.
  bool claim(uint32_t id, uint64_t participant, Clock::time_point now, bool new_life = false);
  // A sample of place `id` from `participant` arrived (not yet judged): a
  // holder heard is not silent (call for every sample of a take before
  // judging any, as WriterLatch::heard).
  void heard(uint32_t id, uint64_t participant, Clock::time_point now) { latch_.heard(id, participant, now); }
  // Place `id` departed (its liveliness lapsed): the next process heard for
  // it may hold it, and till then its holder is still vouched for. A lapse
  // under packet loss is no death: the holder's relays still arrive, and
  // the lockstep tick that waits for them would never end if they waited
  // for its next health, which comes only with the next tick (once seen in
  // a 10-tick run under 30 % loss).
  void departed(uint32_t id) { latch_.open(id); }
  // `participant` holds a place id (0: unknown, always).
  [[nodiscard]] bool vouched(uint64_t participant) const { return latch_.holds_any(participant); }
  // `participant` holds place `id`, or nobody does (0: always).
  [[nodiscard]] bool speaks_for(uint32_t id, uint64_t participant) const;
  // How long a sample of a process that holds no place id waits.
  [[nodiscard]] Clock::duration park_for() const { return takeover_after_ + kParkMargin; }

 private:
  static constexpr Clock::duration kParkMargin = std::chrono::seconds(2);
  WriterLatch latch_;
  Clock::duration takeover_after_;
};

// Samples that wait for their process to be vouched for (PlaceVouch), in
// their order of arrival, at most `bound` of them.
template <typename T>
class Parked {
 public:
  using Clock = std::chrono::steady_clock;
  explicit Parked(std::size_t bound = 65536) : bound_(bound) {}

  // Parks `sample`, heard at `now`. The bound full, the oldest parked sample
  // is pushed out and returned (its receiver refuses it).
  std::optional<T> park(T sample, Clock::time_point now) {
    q_.push_back({std::move(sample), now});
    if (q_.size() <= bound_) return std::nullopt;
    T out = std::move(q_.front().sample);
    q_.pop_front();
    return out;
  }
  // Appends to `ready` every parked sample whose process `vouched(sample)`
  // says is vouched for now, and to `expired` those parked longer than
  // `wait`; both in their order of arrival. The others stay.
  template <typename Vouched>
  void sweep(Clock::time_point now, Clock::duration wait, Vouched&& vouched, std::vector<T>& ready,
             std::vector<T>& expired) {
    std::deque<Entry> kept;
    for (auto& e : q_) {
      if (vouched(e.sample)) {
        ready.push_back(std::move(e.sample));
      } else if (now - e.since > wait) {
        expired.push_back(std::move(e.sample));
      } else {
        kept.push_back(std::move(e));
      }
    }
    q_.swap(kept);
  }
  // Every parked sample, oldest first; none is left (the end of a run).
  std::vector<T> take_all() {
    std::vector<T> out;
    for (auto& e : q_) out.push_back(std::move(e.sample));
    q_.clear();
    return out;
  }
  [[nodiscard]] std::size_t size() const { return q_.size(); }
  [[nodiscard]] bool empty() const { return q_.empty(); }

 private:
  struct Entry {
    T sample;
    Clock::time_point since;
  };
  std::size_t bound_;
  std::deque<Entry> q_;
};

}  // namespace pheromesh::core
