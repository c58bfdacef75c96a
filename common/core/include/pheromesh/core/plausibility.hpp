// What a receiver refuses although the sample is well formed (issue 16,
// docs/architecture.md "What a receiver refuses"). messages.hpp checks
// structure and ranges; these checks ask whether a sample can come from the
// swarm that runs: a UAV id of the swarm, a sequence number or tick the sender
// can have reached, a value the layer can hold, a state the UAV can fly to, a
// detection of a real target near the UAV. On the default one-host profile any
// process can write any topic, so these are the receivers' only defence.
// Pure functions, no I/O: the fuzzing harness calls them too.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"

namespace pheromesh::core {

// Why a well-formed sample was refused. The order is on the wire
// (PlaceHealth.refused, UavState.refused): append only.
enum class Refusal : uint8_t {
  UnknownUav = 0,            // a deposit, state, detection or broadcast of a UAV id outside the swarm
  SeqFarAhead = 1,           // a deposit sequence number the UAV cannot have reached yet
  TickFarAhead = 2,          // a tile, halo, field, view or state of a tick the sender cannot have reached yet
  ValueOutOfRange = 3,       // a tile or halo value outside its layer's physical range
  ForeignClock = 4,          // a lockstep clock sample from a writer other than the conductor first heard
  ImplausibleDetection = 5,  // a detection of no target of the scenario, far from the reporting UAV, or sent to a place
                             // agent that does not serve the UAV
  ImplausibleState = 6,      // a UAV state further from the last accepted one than the UAV can fly, or sent to a place
                             // agent that does not serve the UAV
  ForeignWriter =
      7,  // a sample from a writer or process other than the one heard as its sender: a UAV state (writer_latch.hpp), a
          // UAV's detection or broadcast, a place agent's health, relay, tile or forwarded deposit (place_vouch.hpp)
  ImplausibleDeposit =
      8,  // a deposit in a cell its UAV cannot have reached from its last accepted state (check_deposit_reach)
  UnknownPlace =
      9,  // a health, served-UAVs chunk or place report of a (region, replica) the run does not have (check_place_id)
  StaleDetection = 10,  // a detection older than the window of positions kept for its UAV (kKeptPositions)
  ForeignReport = 11,   // a lockstep report (PhaseDone) from a process other than its sender's (report_judge.hpp)
  UnannouncedDeposit =
      12,  // lockstep: a forwarded deposit of a tick whose place phase no longer takes it (DepositDesk)
  RefusedStateDeposit = 13,  // a deposit carried by a UAV state its gateway refused: neither applied nor forwarded
};
static_assert(kRefusalCount == 14, "messages.hpp kRefusalCount: one count per Refusal");
// "unknown_uav", "seq_far_ahead", ... (metrics.json, Prometheus labels).
const char* refusal_name(Refusal r);

// Counts per reason, as carried in health (saturating at 2^32 - 1).
struct RefusalCounts {
  std::array<uint32_t, kRefusalCount> n{};
  void add(Refusal r, uint32_t k = 1);
  [[nodiscard]] uint32_t operator[](Refusal r) const { return n[static_cast<std::size_t>(r)]; }
  [[nodiscard]] uint64_t total() const;
};

// --- UAV ids -------------------------------------------------------------
// UAV ids are 0..swarm-1 (pheromesh run numbers them so).
std::optional<std::string> check_uav_id(uint32_t uav, uint32_t swarm);

// --- deposit sequence numbers ---------------------------------------------
// A UAV numbers its deposits 1, 2, ... and a restarted process continues in
// the next "life" above (life << 24, launch/launcher.cpp). A receiver that
// latched the highest accepted seq of a UAV would be locked out by one forged
// seq 2^32-1; so a seq is accepted only if the UAV can have reached it: at
// most kMaxDepositsPerTick per receiver tick since the last accepted one
// (plus kSeqSlackTicks for clocks that drift), or the start of one of the next
// two lives.
inline constexpr uint32_t kMaxDepositsPerTick = 256;  // far above any policy's (Liu: one per cell entered)
inline constexpr uint32_t kSeqSlackTicks = 64;
inline constexpr uint32_t kSeqLifeShift = 24;
// `last`: the highest accepted seq of this UAV (nullopt: none yet);
// `ticks_since`: receiver ticks since it was accepted (since the start if none).
// A seq not above `last` is the caller's business (duplicate), not refused here.
std::optional<std::string> check_seq_reachable(uint32_t seq, std::optional<uint32_t> last, uint32_t ticks_since);

// --- ticks ---------------------------------------------------------------
// The highest tick a sample can carry (realtime): every process of a run
// starts ticking after the launch, at the run's rate (a late tick restarts
// the schedule, it never bursts), and pausing only holds ticks back. The
// slack is what a sender's clock may be ahead of the receiver's:
// - over several hosts each host's launcher has a launch time of its own,
//   and a LAN run's hosts may be launched up to half a minute apart;
// - on one host (`pheromesh run` without --hosts, $PHEROMESH_RUN_ONE_HOST)
//   every process's launch time is the same instant of the same clock: a
//   tick that fires early and the rounding of whole milliseconds only
//   (issue 28: 30 s let a forged field chunk 250 ticks ahead through).
struct TickSlack {
  double seconds = 30.0;
  uint32_t ticks = 50;
};
inline constexpr TickSlack kLaunchSlack{};
inline constexpr TickSlack kOneHostSlack{2.0, 5};
inline constexpr double kTickSlackSeconds = kLaunchSlack.seconds;
inline constexpr uint32_t kTickSlackTicks = kLaunchSlack.ticks;
uint32_t realtime_tick_ceiling(double seconds_since_launch, double rate_hz, TickSlack slack = kLaunchSlack);
// Lockstep: a sample is at most one tick ahead of the clock the receiver holds.
inline constexpr uint32_t lockstep_tick_ceiling(uint32_t clock_tick) { return clock_tick + 1; }
// `what` names the sample ("state", "tile", ...).
std::optional<std::string> check_tick_reachable(uint32_t tick, uint32_t ceiling, const char* what);

// --- values ----------------------------------------------------------------
struct ValueRange {
  float lo = 0.0F, hi = 0.0F;
};
std::optional<std::string> check_values_in_range(std::span<const float> values, ValueRange range, const char* what);
// A tile against its layer's range (ranges[t.layer]; a layer without one is not checked).
std::optional<std::string> check_tile_range(const TileMsg& t, std::span<const ValueRange> ranges);

// --- motion and detections --------------------------------------------------
// Slack [cell] on top of max_step·ticks: rounding of positions, and the one
// step between a state and the detection made at the same tick.
inline constexpr double kMotionSlackCells = 1.5;
// `last`: the UAV's last accepted state (nullptr: none yet); `start`: its start
// cell; `max_step`: the farthest it flies in one tick [cell/tick]. A first
// state must be reachable from the start cell in its tick; any other from the
// last state in the ticks between them (either way: a repeated older state
// too) - or, with `may_restart` and a tick that went back, from the start cell
// (a restarted process flies again from there, counting ticks from 0).
std::optional<std::string> check_state_motion(const UavStateMsg& s, const UavStateMsg* last, Cell start,
                                              double max_step, bool may_restart);
// A deposit lands where its UAV can have put it (issue 42 D4): within
// `reach` (PolicyTraits::deposit_reach [cell]) of where the UAV was, which
// is at most max_step·(ticks + 1) + kMotionSlackCells from `last` - the
// UAV's last accepted state, whatever its tick (the ticks between it and the
// deposit's; the one step of the deposit's own tick) - or, with none, from
// its start cell in tick + 1 ticks. An infinite reach judges nothing.
std::optional<std::string> check_deposit_reach(const DepositMsg& d, const UavStateMsg* last, Cell start,
                                               double max_step, double reach);
// `targets`: the scenario's targets (and those added during the run); `seen`:
// the reporting UAV's accepted state nearest in time (nullptr: none);
// `sensor_radius` [cell].
std::optional<std::string> check_detection(const DetectionMsg& d, std::span<const Cell> targets,
                                           const UavStateMsg* seen, double sensor_radius, double max_step);
// A receiver keeps a window of each UAV's latest positions (the ground
// station: 128, RunRecorder); `oldest_kept`: the tick of the oldest it keeps
// once older ones were dropped (nullopt: none dropped, every position since
// the UAV's first is kept). A detection of an earlier tick cannot be judged
// against the position of its own tick, and is refused (StaleDetection)
// rather than judged against a later one.
std::optional<std::string> check_detection_kept(const DetectionMsg& d, std::optional<uint32_t> oldest_kept);

}  // namespace pheromesh::core
