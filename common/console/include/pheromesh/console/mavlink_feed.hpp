// The swarm as a MAVLink ground-control station sees it (docs/mavlink.md):
// what the ground station streams over UDP with --mavlink, built from what
// its intake already heard (the run recorder's UAVs, its notes), or what
// `pheromesh replay --mavlink` rebuilt from a recording (mavlink_replay.hpp),
// and the answer to a command. Pure: no socket; the time is passed in, and
// the shell sends the datagrams returned.
//
// Systems: UAV i (0 <= i < 250) is MAVLink system i + 1, component 1 (its
// HEARTBEAT at 1 Hz; GLOBAL_POSITION_INT and ATTITUDE at --mavlink-rate-hz);
// the ground station is system 251 (HEARTBEAT and SYS_STATUS at 1 Hz,
// STATUSTEXT for losses and found targets, ADSB_VEHICLE of every UAV at
// --mavlink-rate-hz, COMMAND_ACK).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pheromesh/console/ground_intake.hpp"
#include "pheromesh/core/geodetic.hpp"
#include "pheromesh/core/result.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/mavlink/command_gate.hpp"
#include "pheromesh/mavlink/frame.hpp"

namespace pheromesh::console {

// Where --mavlink sends: "udp:HOST:PORT".
struct MavlinkTarget {
  std::string host;  // a name or an IPv4 address
  uint16_t port = 0;
};
// Parses `value` of `flag`; the error names the flag and shows the form.
core::Result<MavlinkTarget> parse_mavlink_target(std::string_view value, std::string_view flag = "--mavlink");

inline constexpr double kMavlinkMinRateHz = 0.2;   // [Hz]
inline constexpr double kMavlinkMaxRateHz = 20.0;  // [Hz]
inline constexpr double kMavlinkDefaultRateHz = 4.0;
// The rate of --mavlink-rate-hz, or an error naming the flag and the range.
core::Result<double> check_mavlink_rate(double hz, std::string_view flag = "--mavlink-rate-hz");

inline constexpr uint32_t kMavlinkMaxVehicles = 250;        // UAVs 0..249 are systems 1..250
inline constexpr uint8_t kMavlinkGroundSysid = 251;         // the ground station's own system
inline constexpr uint8_t kMavlinkCompid = 1;                // MAV_COMP_ID_AUTOPILOT1
inline constexpr std::size_t kMavlinkDatagramBytes = 1200;  // frames are packed up to this (below any MTU)
inline constexpr std::size_t kMavlinkTextQueue = 32;        // STATUSTEXTs waiting; more are counted and dropped
inline constexpr std::size_t kMavlinkTextChunks = 4;        // a text is sent in at most 4 chunks of 50 bytes

// A UAV's ADSB_VEHICLE ICAO address (24 bits, a block no real aircraft is
// given by the examples we know: 0xFA0000 + id) and callsign ("PH" + id).
uint32_t mavlink_icao_address(uint32_t uav);
std::string mavlink_callsign(uint32_t uav);

// What the feed needs of a run, from its scenario or a recording's ConsoleInfo.
struct MavlinkRun {
  core::GeoFrame geo;
  double tick_rate_hz = 0;  // [Hz]
  uint32_t regions = 0;
  std::size_t targets = 0;
};
MavlinkRun mavlink_run_of(const core::ScenarioConfig& scenario);

// One UAV as the stream shows it.
struct MavlinkUav {
  uint32_t id = 0;
  uint32_t tick = 0;      // of its newest state (a new one restarts ADS-B tslc)
  double x = 0, y = 0;    // [cell]
  double vx = 0, vy = 0;  // [cell/tick]
  bool alive = true;      // false: lost, it falls silent
  bool finished = false;  // POWEROFF
};
// The swarm at one moment: every UAV heard (by id), and the counters of the
// ground station's SYS_STATUS.
struct MavlinkSwarm {
  std::vector<MavlinkUav> uavs;
  uint32_t places_lost = 0;  // regions
  uint32_t uavs_lost = 0;
  std::size_t targets_found = 0;
};
// The run recorder's view of the swarm (`regions`: the scenario's).
MavlinkSwarm mavlink_swarm_of(const core::RunRecorder& rec, uint32_t regions);

class MavlinkFeed {
 public:
  using Clock = std::chrono::steady_clock;
  struct Stats {
    uint64_t frames = 0;
    uint64_t datagrams = 0;
    uint64_t texts_dropped = 0;  // STATUSTEXTs beyond kMavlinkTextQueue
  };

  // `rate_hz`: positions, attitudes and ADS-B per UAV [Hz], checked by
  // check_mavlink_rate. `start`: time_boot_ms counts from it.
  MavlinkFeed(const MavlinkRun& run, double rate_hz, Clock::time_point start);
  MavlinkFeed(const core::ScenarioConfig& scenario, double rate_hz, Clock::time_point start)
      : MavlinkFeed(mavlink_run_of(scenario), rate_hz, start) {}

  // Pause and resume from any source: a paused UAV is STANDBY.
  void set_paused(bool paused) { paused_ = paused; }
  // Losses, returns and found targets become STATUSTEXTs.
  void note(const IntakeNote& n);
  // Everything due at `now`, packed into datagrams; `rec` is the intake's
  // view of the swarm.
  std::vector<std::vector<uint8_t>> due(const core::RunRecorder& rec, Clock::time_point now) {
    return due(mavlink_swarm_of(rec, regions_), now);
  }
  std::vector<std::vector<uint8_t>> due(const MavlinkSwarm& swarm, Clock::time_point now);
  // A COMMAND_ACK from the ground station to the sender of `c`, signed if `signing` is.
  std::vector<uint8_t> ack(const mavlink::CommandGate::Command& c, uint8_t result,
                           const std::optional<mavlink::Signing>& signing);

  [[nodiscard]] const Stats& stats() const { return stats_; }

 private:
  void heartbeats(const MavlinkSwarm& swarm);
  void positions(const MavlinkSwarm& swarm, Clock::time_point now, uint32_t boot_ms);
  void position(const MavlinkUav& u, Clock::time_point now, uint32_t boot_ms);
  void ground_status(const MavlinkSwarm& swarm);
  void status_text(const std::string& text);
  void put(std::vector<uint8_t> frame);
  uint8_t next_seq(uint8_t sysid) { return seq_[sysid]++; }

  core::GeoFrame geo_;
  double cells_per_tick_to_mps_;  // cell_size_m * tick_rate_hz
  uint32_t regions_;
  std::size_t targets_;
  Clock::duration position_period_;
  Clock::time_point start_, next_heartbeat_, next_position_;
  bool paused_ = false;
  std::array<uint8_t, 256> seq_{};
  std::deque<std::string> texts_;
  uint16_t text_id_ = 0;                            // of the last text sent in chunks
  std::map<uint32_t, Clock::time_point> heard_at_;  // by UAV: when its newest tick arrived (ADS-B tslc)
  std::map<uint32_t, uint32_t> heard_tick_;
  std::vector<std::vector<uint8_t>> out_;  // datagrams of the call under way
  Stats stats_;
};

}  // namespace pheromesh::console
