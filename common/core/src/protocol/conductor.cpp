#include "pheromesh/core/conductor.hpp"

#include <algorithm>
#include <charconv>
#include <utility>

namespace pheromesh::core {

Result<GoneProcesses> parse_gone(const std::string& answer, uint32_t uavs, uint32_t regions) {
  const std::string prefix = "gone ";
  if (answer.rfind(prefix, 0) != 0)
    return Error{"the launcher answered '" + answer + "', not 'gone NAME,...' or 'gone -'"};
  const std::string list = answer.substr(prefix.size());
  GoneProcesses g;
  if (list == "-") return g;
  std::size_t from = 0;
  while (from <= list.size()) {
    const std::size_t comma = std::min(list.find(',', from), list.size());
    const std::string name = list.substr(from, comma - from);
    from = comma + 1;
    const std::size_t dash = name.find('-');
    const std::string role = dash == std::string::npos ? name : name.substr(0, dash);
    uint32_t index = 0;
    uint32_t replica = 0;
    const char* first = name.data() + (dash == std::string::npos ? name.size() : dash + 1);
    const char* last = name.data() + name.size();
    // A standby place agent: place-R.rN.
    if (const std::size_t dot = name.find(".r"); role == "place" && dot != std::string::npos && dot > dash) {
      const auto [rend, rec] = std::from_chars(name.data() + dot + 2, last, replica);
      if (rec != std::errc() || rend != last || replica == 0 || replica > 0xFFFFU) {
        return Error{"the launcher named '" + name + "' among the gone processes; expected place-R.rN with N >= 1"};
      }
      last = name.data() + dot;
    }
    const auto [end, ec] = std::from_chars(first, last, index);
    if (dash == std::string::npos || first == last || ec != std::errc() || end != last) {
      return Error{"the launcher named '" + name + "' among the gone processes; expected uav-N or place-R"};
    }
    if (role == "uav" && index < uavs) {
      g.uavs.push_back(index);
    } else if (role == "place" && index < regions && replica > 0) {
      g.standbys.push_back(place_id(index, static_cast<uint16_t>(replica)));
    } else if (role == "place" && index < regions) {
      g.regions.push_back(index);
    } else {
      return Error{"the launcher named '" + name + "' among the gone processes; this swarm has " +
                   std::to_string(uavs) + " uavs and " + std::to_string(regions) + " place agents"};
    }
  }
  return g;
}

bool LockstepConductor::drop_uav(uint32_t uav) {
  departed_since_.erase(uav);
  return dropped_.insert(uav).second;
}

bool LockstepConductor::drop_region(RegionId r) { return absent_.insert(r).second; }

bool LockstepConductor::on_place_back(uint32_t place) {
  if (!places_gone_.contains(place) || places_killed_.contains(place)) return false;
  // In step: its latest report is of the place phase before the current
  // tick's (in a UAV phase that is the last place phase; in a place phase
  // it is still working on this one) or of the current one. Before the
  // first place phase every replica is in step.
  const auto it = done_.find(process_key(kRolePlace, place));
  const bool reported_place = it != done_.end() && it->second.phase == static_cast<uint8_t>(ClockPhase::Place);
  const bool in_step = reported_place ? it->second.tick + 1 >= tick_ : tick_ == 0;
  if (!in_step || (phase_ != ClockPhase::Uav && phase_ != ClockPhase::Place)) return false;
  places_gone_.erase(place);
  return true;
}

namespace {
// Ticks of bookkeeping kept: a UAV phase needs the tick before it only.
constexpr std::size_t kKeepTicks = 4;
template <typename M>
void trim(M& by_tick) {
  while (by_tick.size() > kKeepTicks) by_tick.erase(by_tick.begin());
}
}  // namespace

bool LockstepConductor::on_uav_state(uint32_t uav, uint32_t tick, TileCoord tile, ServedUav pose) {
  if (dropped_.contains(uav)) return false;  // a sample it wrote before it was killed
  pose.uav = uav;
  positions_[tick][uav] = {tile, pose};
  trim(positions_);
  return departed_since_.erase(uav) > 0;
}

bool LockstepConductor::on_uav_refused(uint32_t uav, uint32_t tick) {
  if (dropped_.contains(uav)) return false;
  refused_[tick].insert(uav);
  trim(refused_);
  return departed_since_.erase(uav) > 0;
}

bool LockstepConductor::on_uav_finished(uint32_t uav) {
  return !dropped_.contains(uav) && departed_since_.erase(uav) > 0;
}

void LockstepConductor::on_broadcast(uint32_t uav, uint32_t tick) {
  broadcasters_[tick].insert(uav);
  trim(broadcasters_);
}

void LockstepConductor::on_phase_done(const PhaseDoneMsg& m) {
  // A report of an older tick does not replace a newer one: a lagging
  // replica's copy of a gateway's report of a UAV's phase comes after the
  // first replica's report of the next tick.
  auto [it, fresh] = done_.try_emplace(m.process, m);
  if (!fresh && m.tick >= it->second.tick) it->second = m;
}

bool LockstepConductor::on_uav_departed(uint32_t uav, Clock::time_point now) {
  if (dropped_.contains(uav)) return false;  // known: killed at a tick
  return departed_since_.emplace(uav, now).second;
}

bool LockstepConductor::gone_for_good(uint32_t uav, Clock::time_point now) const {
  auto it = departed_since_.find(uav);
  if (it == departed_since_.end()) return false;
  auto heard = heard_.find(uav);
  const Clock::time_point since = heard == heard_.end() ? it->second : std::max(it->second, heard->second);
  return now - since > o_.departed_grace;
}

ClockMsg LockstepConductor::begin_phase(uint32_t tick, ClockPhase phase, Clock::time_point now, bool next_uav_phase) {
  tick_ = tick;
  phase_ = phase;
  deadline_ = now + (phase == ClockPhase::Ready ? o_.start_timeout : o_.phase_timeout);
  begun_at_ = now;
  timed_ = false;
  next_uav_phase_ = next_uav_phase && phase == ClockPhase::Place && o_.standbys == 0;
  // The UAV phase just completed: what it reported for absent regions is lost.
  if (phase == ClockPhase::Place) deposits_lost_ += std::exchange(lost_this_tick_, 0);
  if (phase == ClockPhase::Uav) lost_this_tick_ = 0;
  ClockMsg m = announce(tick, phase);
  if (next_uav_phase_) {
    // What the UAV clock of tick+1 announces (a UAV waits for the broadcasts
    // of `tick` it lists), on this clock.
    ClockMsg uav = announce(tick + 1, ClockPhase::Uav);
    m.next_uav_phase = true;
    m.broadcasts = uav.broadcasts;
    m.occupancy = std::move(uav.occupancy);
  }
  return m;
}

void LockstepConductor::turn_to_next_uav_phase(Clock::time_point now) {
  next_uav_phase_ = false;
  tick_ += 1;
  phase_ = ClockPhase::Uav;
  deadline_ = now + o_.phase_timeout;
  begun_at_ = now;
  timed_ = false;
  lost_this_tick_ = 0;
}

void LockstepConductor::record_time(Clock::time_point now) {
  if (timed_) return;
  timed_ = true;
  (phase_ == ClockPhase::Uav ? times_.uav_ms : times_.place_ms)
      .push_back(std::chrono::duration<double, std::milli>(now - begun_at_).count());
}

ClockMsg LockstepConductor::stop(uint32_t ticks) {
  ClockMsg m;
  m.tick = ticks;
  m.phase = static_cast<uint8_t>(ClockPhase::Stop);
  return m;
}

ClockMsg LockstepConductor::announce(uint32_t tick, ClockPhase phase) const {
  ClockMsg m;
  m.tick = tick;
  m.phase = static_cast<uint8_t>(phase);
  m.absent.assign(absent_.begin(), absent_.end());
  if (phase == ClockPhase::Place) {
    // The deposits of this tick each region must apply, as the UAVs reported,
    // and the states of this tick each region's place agent must hold.
    for (const auto& [region, n] : deposits_reported_) m.deposits.push_back({region, n});
    for (const auto& [region, n] : states_reported_) m.states.push_back({region, n});
    // Every UAV whose state of this tick is here, with its gateway: the
    // place agent that composes its view (a UAV with neither home nor
    // backup present gets none). Each place agent sends the tiles these
    // UAVs' views need and shows them as neighbours (docs/architecture.md,
    // "Time").
    if (auto it = positions_.find(tick); it != positions_.end()) {
      for (const auto& [uav, heard] : it->second) {
        const auto gateway = gateway_region(uav, o_.regions, [&](RegionId r) { return absent_.contains(r); });
        if (!gateway || dropped_.contains(uav)) continue;
        ServedUav u = heard.pose;
        u.region = *gateway;
        m.served.push_back(u);
      }
    }
    return m;
  }
  if (phase != ClockPhase::Uav || tick == 0) return m;
  // UAV phase k: the UAVs over each tile after UAV phase k-1, and how many
  // broadcasts it produced (each UAV waits until it holds all of them).
  if (auto it = positions_.find(tick - 1); it != positions_.end()) {
    std::map<std::pair<int32_t, int32_t>, uint32_t> count;
    for (const auto& [uav, heard] : it->second) ++count[{heard.tile.tx, heard.tile.ty}];
    for (const auto& [t, n] : count) m.occupancy.push_back({{t.first, t.second}, n});
  }
  if (auto it = broadcasters_.find(tick - 1); it != broadcasters_.end()) {
    m.broadcasts = static_cast<uint32_t>(it->second.size());
  }
  return m;
}

LockstepConductor::Status LockstepConductor::ready_status(Clock::time_point now) const {
  // Every UAV and every place agent, each once.
  Status s;
  const auto ready = [&](uint32_t r, uint32_t id) {
    auto it = done_.find(process_key(r, id));
    return it != done_.end() && it->second.phase == static_cast<uint8_t>(ClockPhase::Ready);
  };
  for (uint32_t id = 0; id < o_.uavs; ++id) {
    if (!dropped_.contains(id) && !ready(kRoleUav, id)) s.uavs_not_ready.push_back(id);
  }
  for (uint32_t id = 0; id < o_.regions; ++id) {
    if (!absent_.contains(id) && !ready(kRolePlace, id)) s.regions_not_ready.push_back(id);
  }
  s.waiting = static_cast<uint32_t>(s.uavs_not_ready.size() + s.regions_not_ready.size());
  s.complete = s.waiting == 0;
  s.timed_out = !s.complete && now > deadline_;
  return s;
}

uint32_t LockstepConductor::not_reported(Clock::time_point now, Status* who) const {
  const bool uav_phase = phase_ == ClockPhase::Uav;
  const uint32_t role = uav_phase ? kRoleUav : kRolePlace;
  const uint32_t count = uav_phase ? o_.uavs : o_.regions;
  const auto reported = [&](uint32_t key) {
    auto it = done_.find(key);
    return it != done_.end() && it->second.tick == tick_ && it->second.phase == static_cast<uint8_t>(phase_);
  };
  uint32_t waiting = 0;
  for (uint32_t id = 0; id < count; ++id) {
    if (uav_phase && !waited_for_uav(id, now)) continue;  // dead UAVs are not waited for
    if (!uav_phase && absent_.contains(id)) continue;     // nor absent place agents
    if (!uav_phase && o_.standbys > 0) {
      // Every live replica of the region; if none lives, its primary (the
      // tick cannot be exact without it: the phase runs into its timeout).
      bool any = false;
      for (uint32_t rep = 0; rep <= o_.standbys; ++rep) {
        const uint32_t place = place_id(id, static_cast<uint16_t>(rep));
        if (places_gone_.contains(place)) continue;
        any = true;
        if (!reported(process_key(role, place))) note(waiting, who, id);
      }
      if (!any && !reported(process_key(role, id))) note(waiting, who, id);
      continue;
    }
    if (!reported(process_key(role, id))) note(waiting, who, id);
  }
  return waiting;
}

void LockstepConductor::note(uint32_t& waiting, Status* who, uint32_t id) const {
  ++waiting;
  if (who == nullptr) return;
  auto& ids = phase_ == ClockPhase::Uav ? who->uavs_not_ready : who->regions_not_ready;
  if (ids.empty() || ids.back() != id) ids.push_back(id);
}

uint32_t LockstepConductor::tally_uav_reports(Clock::time_point now, Status* who) {
  // Every UAV's state and reported broadcast of this tick must be here
  // before the next announcements are computed from them.
  uint32_t waiting = 0;
  uint32_t broadcasts = 0;
  deposits_reported_.clear();
  states_reported_.clear();
  lost_this_tick_ = 0;
  auto pos = positions_.find(tick_);
  auto refused = refused_.find(tick_);
  // Its state, or its gateway's refusal of it (an answer too).
  const auto answered = [&](uint32_t id) {
    return (pos != positions_.end() && pos->second.contains(id)) ||
           (refused != refused_.end() && refused->second.contains(id));
  };
  for (uint32_t id = 0; id < o_.uavs; ++id) {
    auto it = done_.find(process_key(kRoleUav, id));
    if (!waited_for_uav(id, now) || it == done_.end()) continue;
    broadcasts += it->second.broadcasts;
    // A UAV's state and deposits go through its gateway (its home, else its
    // backup); with none alive nothing is forwarded, and an absent owner
    // applies nothing.
    const auto gateway = gateway_region(id, o_.regions, [&](RegionId r) { return absent_.contains(r); });
    if (gateway) ++states_reported_[*gateway];
    // Its gateway refused its state of this tick: it applies and forwards
    // none of the deposits the state carried (it rejects them,
    // core::CarriedDeposits::Reject), so no region waits for them.
    if (gateway && refused != refused_.end() && refused->second.contains(id)) {
      if (!answered(id)) note(waiting, who, id);
      continue;
    }
    for (const auto& rc : it->second.deposits) {
      if (!gateway || absent_.contains(rc.region)) {
        lost_this_tick_ += rc.count;
      } else {
        deposits_reported_[rc.region] += rc.count;
      }
    }
    if (!answered(id)) note(waiting, who, id);
  }
  auto b = broadcasters_.find(tick_);
  if ((b == broadcasters_.end() ? 0U : static_cast<uint32_t>(b->second.size())) < broadcasts) ++waiting;
  return waiting;
}

LockstepConductor::Status LockstepConductor::status(Clock::time_point now) {
  if (phase_ == ClockPhase::Ready) return ready_status(now);
  if (next_uav_phase_ && not_reported(now) == 0) {
    // The place phase is complete; the UAV phase it began goes on (its
    // reports may all be here already).
    record_time(now);
    turn_to_next_uav_phase(now);
  }
  Status s;
  s.waiting = not_reported(now, &s);
  if (s.waiting == 0 && phase_ == ClockPhase::Uav) s.waiting = tally_uav_reports(now, &s);
  // A fused place phase is complete with the UAV phase after it.
  s.complete = s.waiting == 0 && !next_uav_phase_;
  s.timed_out = !s.complete && now > deadline_;
  if (s.complete) record_time(now);
  return s;
}

}  // namespace pheromesh::core
