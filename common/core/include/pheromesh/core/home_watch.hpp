// When a realtime UAV takes its home place agent for gone and moves to its
// backup gateway (core/faults.hpp, "kill place:R"; docs/faults.md): after a
// silence of its home's views, with time passed in so that tests drive it
// by hand. Lockstep needs no watch: the conductor names the absent regions
// (core::gateway_region).
//
// Rules:
//  * The silence is at least 2 s and two leases; four leases with a hot
//    standby, which takes over within one and a half (silence_for).
//  * It counts from the start of the flight, from the last view heard, and
//    from the end of a pause (a paused swarm sends no views).
//  * The caller judges after it took the views that were waiting: a UAV
//    whose own thread was held up finds its home's views in its inbox, and
//    a home that kept writing is not gone.
//  * A UAV without a backup (one region) never moves; one that moved stays
//    with its backup (move_to_backup is true once).
#pragma once

#include <chrono>
#include <cstdint>

namespace pheromesh::core {

class HomeWatch {
 public:
  using Clock = std::chrono::steady_clock;

  [[nodiscard]] static std::chrono::milliseconds silence_for(uint32_t lease_ms, bool standby);

  // `has_backup`: the swarm has more than one region. The silence counts
  // from start().
  HomeWatch(std::chrono::milliseconds silence, bool has_backup) : silence_(silence), has_backup_(has_backup) {}

  // The flight starts, or resumes after a pause, at `now`: the silence counts from there.
  void start(Clock::time_point now) { last_heard_ = now; }
  // A view from the home was taken at `at`.
  void heard(Clock::time_point at) {
    if (at > last_heard_) last_heard_ = at;
  }
  // Whether the UAV moves to its backup now: its home has been silent for
  // longer than the silence. True once; the watch ends with it.
  [[nodiscard]] bool move_to_backup(Clock::time_point now);

  [[nodiscard]] bool moved() const { return moved_; }
  [[nodiscard]] std::chrono::milliseconds silence() const { return silence_; }
  [[nodiscard]] Clock::time_point last_heard() const { return last_heard_; }

 private:
  std::chrono::milliseconds silence_;
  bool has_backup_;
  bool moved_ = false;
  Clock::time_point last_heard_{};
};

}  // namespace pheromesh::core
