#include "pheromesh/core/run_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/uav_core.hpp"

namespace pheromesh::core {

std::vector<Cell> all_starts(const ScenarioConfig& s) { return start_cells(s); }

RunRecorder::RunRecorder(const ScenarioConfig& scenario, const World& world)
    : scenario_(&scenario),
      world_(&world),
      geo_(scenario.geometry()),
      coverage_(world, all_starts(scenario), policy_traits(scenario).sensor_radius),
      acquisitions_(scenario.targets.size()),
      traits_(policy_traits(scenario)),
      max_step_(traits_.max_step),
      sensor_radius_(traits_.sensor_radius),
      tick_ceiling_(std::numeric_limits<uint32_t>::max()) {}

bool RunRecorder::on_uav_state(const UavStateMsg& s) {
  if (check_uav_state(s, geo_)) {
    ++samples_rejected_;
    return false;
  }
  // Forged states must not move coverage (plausibility.hpp).
  if (check_uav_id(s.uav, scenario_->uavs)) {
    refused_.add(Refusal::UnknownUav);
    return false;
  }
  if (check_tick_reachable(s.tick, tick_ceiling_, "state")) {
    refused_.add(Refusal::TickFarAhead);
    return false;
  }
  if (s.implausible) {
    on_refused_state(s);
    return true;
  }
  auto found = uavs_.find(s.uav);
  const bool known = found != uavs_.end() && found->second.heard;
  if (known && stale_copy(s, found->second)) {
    // Two gateways relay each UAV's states (a home's replicas, a backup) and
    // lockstep re-sends come late: an older copy arriving after a newer state
    // must not replace it (the run's deposits_sent fell by the deposits in
    // between: applied 3165 > sent 3113 with a standby on another host). Its
    // position at its tick is still true.
    ++states_stale_;
    coverage_.observe(state_cell(s), s.tick);
    return true;
  }
  // Only a UAV lost before may start again from its start cell (a restart).
  const UavStateMsg* before = known ? &found->second.last : nullptr;
  const bool may_restart = !known || !found->second.alive;
  if (check_state_motion(s, before, uav_start(*scenario_, traits_, s.uav), max_step_, may_restart)) {
    refused_.add(Refusal::ImplausibleState);
    return false;
  }
  auto& u = uavs_[s.uav];
  u.heard = true;
  // Shao 2020 Sec. 5: the leader hands over to the search at the target region.
  if (!leader_arrival_ && u.last.role == static_cast<uint8_t>(Role::Leader) &&
      s.role == static_cast<uint8_t>(Role::Searcher)) {
    leader_arrival_ = s.tick;
  }
  // A UAV back after it was lost with a lower count is a restarted process:
  // its earlier life's deposits still count.
  if (starts_new_life(s)) u.earlier_lives_deposits += u.last.deposits_sent;
  // Not a stale copy (above): a tick that went back is a new life.
  const bool new_life = !u.recent.empty() && s.tick <= u.recent.back().tick;
  if (new_life) {
    u.recent.clear();
    u.forgot = false;
  }
  u.last = s;
  u.heard_tick = new_life ? s.tick : std::max(u.heard_tick, s.tick);
  if (u.recent.empty() || s.tick > u.recent.back().tick) {
    u.recent.push_back({s.tick, static_cast<float>(s.x), static_cast<float>(s.y)});
    if (u.recent.size() > UavStatus::kRecentFixes) {
      u.recent.pop_front();
      u.forgot = true;
    }
  }
  u.alive = true;
  u.finished = u.finished || s.finished;
  max_tick_ = std::max(max_tick_, s.tick);
  coverage_.observe(state_cell(s), s.tick);
  count_in_series(s.uav, s.tick, s.deposits_sent + u.earlier_lives_deposits);
  if (keep_tracks_) tracks_.push_back({s.tick, s.uav, s.x, s.y, s.role});
  release_pending(u, s.uav, s.tick);
  return true;
}

void RunRecorder::release_pending(const UavStatus& u, uint32_t uav, uint32_t tick) {
  // The detections of this UAV that waited for its state of their tick.
  auto ready = std::stable_partition(pending_.begin(), pending_.end(),
                                     [&](const DetectionMsg& d) { return d.uav != uav || d.tick > tick; });
  std::vector<DetectionMsg> now(ready, pending_.end());
  pending_.erase(ready, pending_.end());
  for (const auto& d : now) {
    if (!u.heard) {
      judge(d, nullptr);
      continue;
    }
    judge_kept(u, d);
  }
}

void RunRecorder::judge_kept(const UavStatus& u, const DetectionMsg& d) {
  const std::optional<uint32_t> oldest =
      u.forgot && !u.recent.empty() ? std::optional<uint32_t>(u.recent.front().tick) : std::nullopt;
  if (check_detection_kept(d, oldest)) {
    refused_.add(Refusal::StaleDetection);
    return;
  }
  const UavStateMsg seen = nearest_state(u, d.tick);
  judge(d, &seen);
}

void RunRecorder::on_refused_state(const UavStateMsg& s) {
  auto [it, fresh] = uavs_.try_emplace(s.uav);
  UavStatus& u = it->second;
  if (fresh) u.last.uav = s.uav;
  RefusedStates& r = refused_states_[s.uav];
  if (r.count == 0) {
    r.first = s;
    r.from_start = !u.heard;
    r.accepted = u.last;
    r.start = uav_start(*scenario_, traits_, s.uav);
  }
  if (r.count == 0 || s.tick > r.last_tick) {
    ++r.count;
    r.last_tick = s.tick;
  }
  // An older copy changes nothing (RunRecorder::stale_copy).
  if (u.heard && s.tick < u.last.tick) return;
  // The UAV's own counters are true whatever its position: deposits sent
  // (the run's accounting), samples, its refusals, whether it finished.
  u.last.deposits_sent = s.deposits_sent;
  u.last.tile_samples_received = s.tile_samples_received;
  u.last.samples_received = s.samples_received;
  u.last.ticks_late = s.ticks_late;
  u.last.tick_gap_max_ms = s.tick_gap_max_ms;
  u.last.tick_gaps_over_2 = s.tick_gaps_over_2;
  u.last.deposits_unconfirmed = s.deposits_unconfirmed;
  u.last.refused = s.refused;
  u.alive = true;
  u.finished = u.finished || s.finished;
  u.heard_tick = std::max(u.heard_tick, s.tick);
  max_tick_ = std::max(max_tick_, s.tick);
  count_in_series(s.uav, s.tick, s.deposits_sent + u.earlier_lives_deposits);
  release_pending(u, s.uav, s.tick);
}

uint64_t RunRecorder::states_refused() const {
  uint64_t n = 0;
  for (const auto& [uav, r] : refused_states_) n += r.count;
  return n;
}

UavStateMsg RunRecorder::nearest_state(const UavStatus& u, uint32_t tick) {
  // recent only grows in tick (a tick that went back started it again).
  const auto it = std::lower_bound(u.recent.begin(), u.recent.end(), tick,
                                   [](const UavStatus::Fix& f, uint32_t t) { return f.tick < t; });
  if (it == u.recent.end()) return u.last;
  UavStateMsg at;
  at.uav = u.last.uav;
  at.tick = it->tick;
  at.x = it->x;
  at.y = it->y;
  return at;
}

void RunRecorder::judge(const DetectionMsg& d, const UavStateMsg* seen) {
  if (check_detection(d, world_->targets(), seen, sensor_radius_, max_step_)) {
    refused_.add(Refusal::ImplausibleDetection);
    return;
  }
  if (acquisitions_.acquire(d.target, d.tick)) first_acquisitions_.push_back(d);
}

bool RunRecorder::on_detection(const DetectionMsg& d) {
  if (d.target < 0 || static_cast<std::size_t>(d.target) >= acquisitions_.size()) {
    ++samples_rejected_;
    return false;
  }
  if (check_uav_id(d.uav, scenario_->uavs)) {
    refused_.add(Refusal::UnknownUav);
    return false;
  }
  auto it = uavs_.find(d.uav);
  const bool seen = it != uavs_.end() && it->second.heard && it->second.last.tick >= d.tick;
  // Bounded: a flood of detections ahead of every state is judged at once.
  constexpr std::size_t kMaxPending = 4096;
  if (!seen && pending_.size() < kMaxPending) {
    pending_.push_back(d);
    return true;
  }
  if (it == uavs_.end() || !it->second.heard) {
    judge(d, nullptr);
    return true;
  }
  judge_kept(it->second, d);
  return true;
}

void RunRecorder::judge_pending_detections() {
  std::vector<DetectionMsg> left;
  left.swap(pending_);
  for (const auto& d : left) {
    auto it = uavs_.find(d.uav);
    judge(d, it != uavs_.end() && it->second.heard ? &it->second.last : nullptr);
  }
}

RefusalCounts RunRecorder::refused_by_places() const {
  RefusalCounts c;
  for (const auto& [id, h] : replica_health_) {
    for (std::size_t i = 0; i < kRefusalCount; ++i) c.add(static_cast<Refusal>(i), h.refused[i]);
  }
  return c;
}

RefusalCounts RunRecorder::refused_by_uavs() const {
  RefusalCounts c;
  for (const auto& [id, u] : uavs_) {
    for (std::size_t i = 0; i < kRefusalCount; ++i) c.add(static_cast<Refusal>(i), u.last.refused[i]);
  }
  return c;
}

std::vector<DetectionMsg> RunRecorder::take_first_acquisitions() {
  std::vector<DetectionMsg> out;
  out.swap(first_acquisitions_);
  return out;
}

void RunRecorder::on_target_event(const TargetEventMsg& e) {
  if (e.kind != static_cast<uint8_t>(MarkEvent::Kind::Revisited)) return;
  // The same event from two replicas of a region (standbys with shared
  // ownership publish it too) counts once.
  const auto same = [&](const TargetEventMsg& x) {
    return x.region == e.region && x.tick == e.tick && x.cell.x == e.cell.x && x.cell.y == e.cell.y &&
           x.response_ticks == e.response_ticks;
  };
  if (std::any_of(revisits_.begin(), revisits_.end(), same)) return;
  revisits_.push_back(e);
}

namespace {

// The counters of `h` with those of the earlier lives added.
HealthMsg with_earlier_lives(HealthMsg h, const HealthMsg& banked) {
  h.deposits_received += banked.deposits_received;
  h.deposits_applied += banked.deposits_applied;
  h.deposits_rejected += banked.deposits_rejected;
  h.deposits_duplicate += banked.deposits_duplicate;
  h.halos_missing += banked.halos_missing;
  h.bytes_received += banked.bytes_received;
  h.tick_gaps_over_2 += banked.tick_gaps_over_2;
  h.tick_gap_max_ms = std::max(h.tick_gap_max_ms, banked.tick_gap_max_ms);
  for (std::size_t i = 0; i < h.refused.size(); ++i) h.refused[i] += banked.refused[i];
  return h;
}

}  // namespace

bool RunRecorder::on_health(const HealthMsg& raw) {
  const uint32_t id = place_id(raw.region, raw.replica);
  // A life's counters start at 0: keep what the earlier lives counted
  // (before, a restarted place agent's record replaced its dead life's, and
  // the run's applied deposits fell at the restart). A late record of an
  // earlier life changes nothing.
  if (auto it = life_latest_.find(id); it != life_latest_.end()) {
    if (raw.life < it->second.life) return false;
    if (raw.life > it->second.life) banked_lives_[id] = with_earlier_lives(it->second, banked_lives_[id]);
  }
  life_latest_[id] = raw;
  const auto banked = banked_lives_.find(id);
  const HealthMsg h = banked == banked_lives_.end() ? raw : with_earlier_lives(raw, banked->second);
  const bool back = departed_places_.erase(id) > 0 && !h.finished;
  replica_health_[id] = h;
  ledger_by_tick_[id].push_back({h.tick, h.deposits_received, h.deposits_applied, h.deposits_rejected});
  auto& best = health_[h.region];
  if (best.region != h.region || best.replica == h.replica || h.deposits_received > best.deposits_received ||
      (h.deposits_received == best.deposits_received && h.replica < best.replica)) {
    best = h;
  }
  return back;
}

bool RunRecorder::region_departed(RegionId r) const {
  bool any = false;
  for (const auto& [id, h] : replica_health_) {
    if (place_id_region(id) != r) continue;
    any = true;
    if (!departed_places_.contains(id)) return false;
  }
  // Lost before its first health: departed if a departure was seen.
  if (!any) {
    for (const auto& [id, gone] : departed_places_) {
      if (place_id_region(id) == r) return true;
    }
  }
  return any;
}

std::optional<uint16_t> RunRecorder::region_owner(RegionId r) const {
  std::optional<uint16_t> best;
  for (const auto& [id, h] : replica_health_) {
    if (place_id_region(id) != r || departed_places_.contains(id) || h.finished) continue;
    if (!best || place_id_replica(id) < *best) best = place_id_replica(id);
  }
  return best;
}

uint32_t RunRecorder::replicas_alive(RegionId r) const {
  uint32_t n = 0;
  for (const auto& [id, h] : replica_health_) {
    if (place_id_region(id) == r && !departed_places_.contains(id) && !h.finished) ++n;
  }
  return n;
}

uint32_t RunRecorder::regions_alive() const {
  uint32_t n = 0;
  for (const auto& [r, h] : health_) n += replicas_alive(r) > 0 ? 1 : 0;
  return n;
}

uint64_t RunRecorder::deposits_lost() const {
  uint64_t received = 0;
  for (const auto& [r, h] : health_) received += h.deposits_received;
  const uint64_t sent = deposits_sent();
  return sent > received ? sent - received : 0;
}

uint64_t RunRecorder::deposits_unconfirmed_by_uavs() const {
  uint64_t n = 0;
  for (const auto& [id, u] : uavs_) n += u.last.deposits_unconfirmed;
  return n;
}

bool RunRecorder::on_uav_departed(const UavDeparture& d) {
  if (check_uav_id(d.uav, scenario_->uavs)) return false;  // no UAV of the swarm
  auto it = uavs_.find(d.uav);
  if (d.last_tick && it != uavs_.end() && it->second.heard && it->second.alive && !it->second.finished &&
      *d.last_tick < it->second.last.tick) {
    ++departures_stale_;
    return false;
  }
  uavs_[d.uav].alive = false;
  return true;
}

void RunRecorder::on_place_departed(uint32_t place) { departed_places_[place] = true; }

std::string role_name(uint8_t role) {
  switch (static_cast<Role>(role)) {
    case Role::Searcher:
      return "searcher";
    case Role::Leader:
      return "leader";
    case Role::Follower:
      return "follower";
  }
  return "role-" + std::to_string(role);
}

std::optional<uint32_t> first_tick_at_coverage(const std::vector<TickRow>& rows, double share) {
  for (const TickRow& r : rows) {
    if (r.coverage >= share) return r.tick;
  }
  return std::nullopt;
}

std::optional<uint32_t> all_targets_found_tick(const AcquisitionTracker& a) {
  if (a.size() == 0 || a.found() != a.size()) return std::nullopt;
  const auto ticks = a.acquisition_ticks();
  return ticks.back();
}

std::vector<TickRow> RunRecorder::tick_series() const {
  const std::size_t n = static_cast<std::size_t>(max_tick_) + 1;
  std::vector<TickRow> rows(n);
  const std::vector<int64_t> covered = coverage_.covered_by_tick(max_tick_);
  const auto reachable = static_cast<double>(coverage_.reachable_cells());
  // Changes per tick, summed below: deposits sent (count_in_series), UAVs
  // heard at exactly that tick, targets first found.
  std::vector<int64_t> sent_delta(sent_delta_.begin(),
                                  sent_delta_.begin() + static_cast<std::ptrdiff_t>(std::min(n, sent_delta_.size())));
  sent_delta.resize(n, 0);
  for (std::size_t k = 0; k < std::min(n, reporting_.size()); ++k) rows[k].uavs_reporting = reporting_[k];
  std::vector<uint32_t> found(n, 0);
  for (const uint32_t t : acquisitions_.acquisition_ticks()) {
    if (t < n) ++found[t];
  }
  // Per region, its replicas' latest health of each tick or before; the
  // region counts the replica that received the most (as health() does).
  std::map<RegionId, std::vector<std::vector<const LedgerPoint*>>> by_region;
  for (const auto& [id, records] : ledger_by_tick_) {
    std::vector<const LedgerPoint*> latest(n, nullptr);
    for (const LedgerPoint& h : records) {
      // A place agent that ticked past the last UAV state (realtime) counts
      // at the last row.
      const LedgerPoint*& slot = latest[std::min<std::size_t>(h.tick, n - 1)];
      // Of two records of one tick, the larger ledger (a final record
      // repeats its replica's last tick).
      if (slot == nullptr || h.received >= slot->received) slot = &h;
    }
    for (std::size_t k = 1; k < n; ++k) {
      if (latest[k] == nullptr) latest[k] = latest[k - 1];
    }
    by_region[place_id_region(id)].push_back(std::move(latest));
  }
  int64_t sent = 0;
  uint32_t targets = 0;
  for (std::size_t k = 0; k < n; ++k) {
    TickRow& r = rows[k];
    r.tick = static_cast<uint32_t>(k);
    r.covered_cells = covered[k];
    r.coverage = reachable > 0 ? static_cast<double>(covered[k]) / reachable : 0.0;
    targets += found[k];
    r.targets_found = targets;
    sent += sent_delta[k];
    r.deposits_sent = static_cast<uint64_t>(std::max<int64_t>(sent, 0));
    for (const auto& [region, replicas] : by_region) {
      const LedgerPoint* best = nullptr;
      for (const auto& latest : replicas) {
        const LedgerPoint* h = latest[k];
        if (h != nullptr && (best == nullptr || h->received > best->received)) best = h;
      }
      if (best == nullptr) continue;
      r.deposits_applied += best->applied;
      r.deposits_rejected += best->rejected;
    }
  }
  return rows;
}

void RunRecorder::count_in_series(uint32_t uav, uint32_t tick, uint64_t sent) {
  // Called with the accepted, non-stale states only: per UAV their ticks
  // rise, or repeat (a later state of one tick replaces the earlier one's
  // count), or fall (a restarted UAV's new life starts at tick 0 again).
  if (tick >= sent_delta_.size()) {
    sent_delta_.resize(static_cast<std::size_t>(tick) + 1, 0);
    reporting_.resize(static_cast<std::size_t>(tick) + 1, 0);
  }
  auto [it, first] = series_mark_.try_emplace(uav, SeriesMark{tick, 0});
  SeriesMark& m = it->second;
  if (first || tick != m.tick) ++reporting_[tick];
  sent_delta_[tick] += static_cast<int64_t>(sent) - static_cast<int64_t>(m.sent);
  m = SeriesMark{tick, sent};
}

std::vector<TrackRow> RunRecorder::tracks() const {
  std::vector<TrackRow> out = tracks_;
  std::stable_sort(out.begin(), out.end(), [](const TrackRow& a, const TrackRow& b) {
    return std::tie(a.tick, a.uav) < std::tie(b.tick, b.uav);
  });
  // Of two states of one UAV and tick (the simulator's closing state, a
  // copy relayed twice), the later one.
  std::vector<TrackRow> unique;
  unique.reserve(out.size());
  for (const TrackRow& t : out) {
    if (!unique.empty() && unique.back().tick == t.tick && unique.back().uav == t.uav) {
      unique.back() = t;
    } else {
      unique.push_back(t);
    }
  }
  return unique;
}

std::vector<TargetEventMsg> RunRecorder::revisit_events() const {
  std::vector<TargetEventMsg> sorted = revisits_;
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) {
    return std::tie(a.tick, a.region, a.cell.y, a.cell.x) < std::tie(b.tick, b.region, b.cell.y, b.cell.x);
  });
  return sorted;
}

std::vector<uint32_t> RunRecorder::revisit_response_ticks() const {
  const std::vector<TargetEventMsg> sorted = revisit_events();
  std::vector<uint32_t> out;
  out.reserve(sorted.size());
  for (const auto& e : sorted) out.push_back(e.response_ticks);
  return out;
}

bool RunRecorder::starts_new_life(const UavStateMsg& s) const {
  auto it = uavs_.find(s.uav);
  if (it == uavs_.end() || !it->second.heard) return false;
  const UavStatus& u = it->second;
  return !u.alive && !u.finished && s.deposits_sent < u.last.deposits_sent;
}

bool RunRecorder::stale_copy(const UavStateMsg& s, const UavStatus& u) {
  // A restarted UAV's realtime ticks start at 0 again, so an older tick is a
  // copy only from a life known to go on: one not lost (its departure ends
  // a life) or one that finished (it flies no more).
  if (!u.alive && !u.finished) return false;
  return s.tick < u.last.tick || (s.tick == u.last.tick && s.deposits_sent < u.last.deposits_sent);
}

uint64_t RunRecorder::deposits_sent() const {
  uint64_t sent = 0;
  for (const auto& [id, u] : uavs_) sent += u.last.deposits_sent + u.earlier_lives_deposits;
  return sent;
}

RefusedMove first_refused_move(const RunRecorder::RefusedStates& r) {
  // As check_state_motion judged it (plausibility.hpp): from the start cell
  // in tick + 1 ticks (tick 0 is after the first move), else from the last
  // accepted state in the ticks between.
  const double x0 = r.from_start ? r.start.x : r.accepted.x;
  const double y0 = r.from_start ? r.start.y : r.accepted.y;
  const uint32_t ticks = r.from_start ? r.first.tick + 1
                                      : (r.first.tick >= r.accepted.tick ? r.first.tick - r.accepted.tick
                                                                         : r.accepted.tick - r.first.tick);
  return {std::hypot(r.first.x - x0, r.first.y - y0), std::max<uint32_t>(ticks, 1)};
}

namespace {
std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}
}  // namespace

std::string describe_first_refusal(const RunRecorder::RefusedStates& r, uint32_t uav, double max_step) {
  return describe_refusal(uav, r.first.tick, first_refused_move(r), r.from_start, max_step);
}

std::string describe_refusal(uint32_t uav, uint32_t tick, RefusedMove m, bool from_start, double max_step) {
  const double allowed = max_step * m.ticks + kMotionSlackCells;
  return "uav " + std::to_string(uav) + "'s state of tick " + std::to_string(tick) +
         " refused as implausible: it moved " + short_number(m.cells) + " cells in " +
         (m.ticks == 1 ? std::string("one tick") : std::to_string(m.ticks) + " ticks") + " from " +
         (from_start ? "its start cell" : "its last accepted state") + " (max_step " + short_number(max_step) +
         " allows " + short_number(allowed) + " with the slack of " + short_number(kMotionSlackCells) + ")";
}

}  // namespace pheromesh::core
