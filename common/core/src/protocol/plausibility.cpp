#include "pheromesh/core/plausibility.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pheromesh::core {

const char* refusal_name(Refusal r) {
  switch (r) {
    case Refusal::UnknownUav:
      return "unknown_uav";
    case Refusal::SeqFarAhead:
      return "seq_far_ahead";
    case Refusal::TickFarAhead:
      return "tick_far_ahead";
    case Refusal::ValueOutOfRange:
      return "value_out_of_range";
    case Refusal::ForeignClock:
      return "foreign_clock";
    case Refusal::ImplausibleDetection:
      return "implausible_detection";
    case Refusal::ImplausibleState:
      return "implausible_state";
    case Refusal::ForeignWriter:
      return "foreign_writer";
    case Refusal::ImplausibleDeposit:
      return "implausible_deposit";
    case Refusal::UnknownPlace:
      return "unknown_place";
    case Refusal::StaleDetection:
      return "stale_detection";
    case Refusal::ForeignReport:
      return "foreign_report";
    case Refusal::UnannouncedDeposit:
      return "unannounced_deposit";
    case Refusal::RefusedStateDeposit:
      return "refused_state_deposit";
  }
  return "unknown";
}

void RefusalCounts::add(Refusal r, uint32_t k) {
  const auto i = static_cast<std::size_t>(r);
  if (i >= n.size()) return;
  n[i] = static_cast<uint32_t>(std::min<uint64_t>(uint64_t{n[i]} + k, std::numeric_limits<uint32_t>::max()));
}

uint64_t RefusalCounts::total() const {
  uint64_t t = 0;
  for (uint32_t v : n) t += v;
  return t;
}

std::optional<std::string> check_uav_id(uint32_t uav, uint32_t swarm) {
  if (uav < swarm) return std::nullopt;
  return "uav " + std::to_string(uav) + " is not one of the swarm's " + std::to_string(swarm);
}

std::optional<std::string> check_seq_reachable(uint32_t seq, std::optional<uint32_t> last, uint32_t ticks_since) {
  const uint32_t base = last.value_or(0);
  if (seq <= base) return std::nullopt;
  // 64-bit: 256 * 2^32 ticks does not fit 32 bits.
  const uint64_t allowance = uint64_t{kMaxDepositsPerTick} * (uint64_t{ticks_since} + kSeqSlackTicks);
  if (uint64_t{seq} - base <= allowance) return std::nullopt;
  // The first deposits of a restarted process: numbered from its life's base.
  const uint32_t life = seq >> kSeqLifeShift, base_life = base >> kSeqLifeShift;
  const uint32_t in_life = seq & ((1U << kSeqLifeShift) - 1U);
  if (life > base_life && life <= base_life + 2 && in_life <= allowance) return std::nullopt;
  return "sequence number " + std::to_string(seq) + " is further ahead of " + std::to_string(base) +
         " than the uav can have deposited in " + std::to_string(ticks_since) + " ticks";
}

uint32_t realtime_tick_ceiling(double seconds_since_launch, double rate_hz, TickSlack slack) {
  if (!std::isfinite(seconds_since_launch) || !std::isfinite(rate_hz) || rate_hz <= 0.0) {
    return std::numeric_limits<uint32_t>::max();
  }
  const double t = std::max(seconds_since_launch, 0.0) + slack.seconds;
  const double c = t * rate_hz + slack.ticks;
  return c >= static_cast<double>(std::numeric_limits<uint32_t>::max()) ? std::numeric_limits<uint32_t>::max()
                                                                        : static_cast<uint32_t>(c);
}

std::optional<std::string> check_tick_reachable(uint32_t tick, uint32_t ceiling, const char* what) {
  if (tick <= ceiling) return std::nullopt;
  return std::string(what) + " of tick " + std::to_string(tick) + ", beyond tick " + std::to_string(ceiling) +
         " that the run can have reached";
}

std::optional<std::string> check_values_in_range(std::span<const float> values, ValueRange range, const char* what) {
  for (float v : values) {
    // NaN fails both comparisons: refused here too.
    if (!(v >= range.lo && v <= range.hi)) {
      return std::string(what) + " value " + std::to_string(v) + " outside [" + std::to_string(range.lo) + ", " +
             std::to_string(range.hi) + "]";
    }
  }
  return std::nullopt;
}

std::optional<std::string> check_tile_range(const TileMsg& t, std::span<const ValueRange> ranges) {
  if (t.layer >= ranges.size()) return std::nullopt;
  return check_values_in_range(t.values, ranges[t.layer], "tile");
}

namespace {
double distance(double x0, double y0, double x1, double y1) { return std::hypot(x1 - x0, y1 - y0); }
}  // namespace

std::optional<std::string> check_state_motion(const UavStateMsg& s, const UavStateMsg* last, Cell start,
                                              double max_step, bool may_restart) {
  const auto reachable = [&](double x, double y, uint32_t ticks) {
    return distance(x, y, s.x, s.y) <= max_step * static_cast<double>(ticks) + kMotionSlackCells;
  };
  const bool from_start = reachable(start.x, start.y, s.tick + 1);  // tick 0 is after the first move
  if (last == nullptr) {
    if (from_start) return std::nullopt;
  } else {
    const uint32_t ticks = s.tick >= last->tick ? s.tick - last->tick : last->tick - s.tick;
    if (reachable(last->x, last->y, ticks) || (may_restart && s.tick < last->tick && from_start)) return std::nullopt;
  }
  return "uav " + std::to_string(s.uav) + " at (" + std::to_string(s.x) + ", " + std::to_string(s.y) + ") at tick " +
         std::to_string(s.tick) + " is further from " + (last == nullptr ? "its start" : "its last state") +
         " than it can fly at " + std::to_string(max_step) + " cells per tick";
}

std::optional<std::string> check_deposit_reach(const DepositMsg& d, const UavStateMsg* last, Cell start,
                                               double max_step, double reach) {
  if (!std::isfinite(reach)) return std::nullopt;
  const double x0 = last != nullptr ? last->x : start.x;
  const double y0 = last != nullptr ? last->y : start.y;
  const uint32_t ticks = last == nullptr ? d.tick : (d.tick >= last->tick ? d.tick - last->tick : last->tick - d.tick);
  const double allowed = reach + max_step * static_cast<double>(ticks + 1) + kMotionSlackCells;
  const double dist = distance(x0, y0, d.cell.x, d.cell.y);
  if (dist <= allowed) return std::nullopt;
  return "a deposit of uav " + std::to_string(d.uav) + " at (" + std::to_string(d.cell.x) + ", " +
         std::to_string(d.cell.y) + ") at tick " + std::to_string(d.tick) + ", " + std::to_string(dist) +
         " cells from " + (last == nullptr ? "its start cell" : "its last accepted state") + " (it reaches " +
         std::to_string(allowed) + ")";
}

std::optional<std::string> check_detection(const DetectionMsg& d, std::span<const Cell> targets,
                                           const UavStateMsg* seen, double sensor_radius, double max_step) {
  if (d.target < 0 || static_cast<std::size_t>(d.target) >= targets.size()) {
    return "detection of target " + std::to_string(d.target) + ", not one of the " + std::to_string(targets.size());
  }
  const Cell t = targets[static_cast<std::size_t>(d.target)];
  if (t.x != d.cell.x || t.y != d.cell.y) {
    return "detection of target " + std::to_string(d.target) + " at (" + std::to_string(d.cell.x) + ", " +
           std::to_string(d.cell.y) + "), which is at (" + std::to_string(t.x) + ", " + std::to_string(t.y) + ")";
  }
  if (seen == nullptr) return "detection by uav " + std::to_string(d.uav) + ", which was never seen flying";
  const uint32_t ticks = d.tick > seen->tick ? d.tick - seen->tick : seen->tick - d.tick;
  const double reach = sensor_radius + max_step * static_cast<double>(ticks + 1) + kMotionSlackCells;
  const double dist = distance(seen->x, seen->y, t.x, t.y);
  if (dist <= reach) return std::nullopt;
  return "detection of target " + std::to_string(d.target) + " by uav " + std::to_string(d.uav) + " " +
         std::to_string(dist) + " cells away (it senses " + std::to_string(sensor_radius) + ")";
}

std::optional<std::string> check_detection_kept(const DetectionMsg& d, std::optional<uint32_t> oldest_kept) {
  if (!oldest_kept || d.tick >= *oldest_kept) return std::nullopt;
  return "a detection of uav " + std::to_string(d.uav) + " at tick " + std::to_string(d.tick) +
         ", older than the oldest of its positions kept (tick " + std::to_string(*oldest_kept) + ")";
}

}  // namespace pheromesh::core
