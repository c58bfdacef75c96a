// A recording streamed to a MAVLink ground-control station as the live
// ground station streamed its run (`pheromesh replay --mavlink`,
// docs/mavlink.md): the recording's frames are played from the first at the
// pace they were recorded (1 s of recording per second), its last state is
// held once they are all played, and what the frames show becomes what
// MavlinkFeed sends live: positions, heartbeats, ADS-B traffic, the ground
// station's status, and STATUSTEXTs for the losses, returns and found
// targets the frames show.
//
// A station's pause and continue (MAV_CMD_DO_PAUSE_CONTINUE) pause and
// continue the playback: its UAVs turn STANDBY and stand still. Every other
// command (disarm among them: a replay has no swarm to stop) is
// MAV_RESULT_UNSUPPORTED. Pure: no socket; the time is passed in.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "pheromesh/console/mavlink_feed.hpp"
#include "pheromesh/console/recording.hpp"
#include "pheromesh/console/state.hpp"
#include "pheromesh/mavlink/command_gate.hpp"

namespace pheromesh::console {

// What the feed needs of a recorded run: its ConsoleInfo's map place (the
// default GeoFrame, 0° N 0° E with 1 m cells, if the recording has none),
// tick rate, regions, and the targets of its first frame.
MavlinkRun mavlink_run_of(const Recording& rec);

class MavlinkReplay {
 public:
  using Clock = MavlinkFeed::Clock;

  // `rec` must outlive the replay and hold at least one frame. `rate_hz` as
  // checked by check_mavlink_rate; the playback starts at `start`.
  MavlinkReplay(const Recording& rec, double rate_hz, Clock::time_point start);

  // The recording's frames up to the playback time applied, then what the
  // feed sends at `now`.
  std::vector<std::vector<uint8_t>> due(Clock::time_point now);
  // The MAV_RESULT for a verified command taken at `now` (acknowledge it with ack()).
  uint8_t command(const mavlink::CommandGate::Command& c, Clock::time_point now);
  // An unsigned COMMAND_ACK from the ground station's system (a replay has no key).
  std::vector<uint8_t> ack(const mavlink::CommandGate::Command& c, uint8_t result) {
    return feed_.ack(c, result, std::nullopt);
  }

  // Seconds of the recording played, from its first frame.
  [[nodiscard]] double played_s() const { return std::chrono::duration<double>(played_).count(); }
  [[nodiscard]] bool paused() const { return paused_; }
  // Every frame has been played (the last state is held).
  [[nodiscard]] bool ended() const { return next_ == rec_.frames.size(); }
  [[nodiscard]] const MavlinkFeed::Stats& stats() const { return feed_.stats(); }

 private:
  struct Motion {
    uint32_t tick = 0;
    double x = 0, y = 0;    // [cell]
    double vx = 0, vy = 0;  // [cell/tick], from its previous position
  };
  void advance(Clock::time_point now);
  void play(const Frame& f);
  void note_uavs(const Frame& f);
  void note_regions(const Frame& f);
  void note_targets(const Frame& f);
  [[nodiscard]] MavlinkSwarm swarm() const;

  const Recording& rec_;
  MavlinkFeed feed_;
  ConsoleState state_;
  std::size_t next_ = 0;  // frames played
  Clock::duration played_{};
  Clock::time_point last_;
  bool paused_ = false;
  std::map<uint32_t, Motion> motion_;  // by UAV
  std::set<uint32_t> regions_seen_;    // regions seen alive: only these can be lost
};

}  // namespace pheromesh::console
