#include "pheromesh/core/simulator.hpp"

#include <algorithm>
#include <string>
#include <utility>

namespace pheromesh::core {

Simulator::Simulator(ScenarioConfig scenario)
    : scenario_(std::move(scenario)),
      geo_(scenario_.geometry()),
      world_(geo_, scenario_.obstacles, scenario_.targets),
      recorder_(scenario_, world_) {
  for (uint32_t i = 0; i < scenario_.uavs; ++i) uavs_.push_back(std::make_unique<UavCore>(scenario_, world_, i));
  for (RegionId r = 0; r < geo_.region_count(); ++r) places_.push_back(std::make_unique<PlaceCore>(scenario_, r));
  deposits_sent_.assign(uavs_.size(), 0);
  tile_samples_.assign(uavs_.size(), 0);
  inbox_.resize(places_.size());
  last_rings_.resize(places_.size());
  for (RegionId r = 0; r < places_.size(); ++r) last_rings_[r].region = r;  // before its first tick: no ring
  traits_ = policy_traits(scenario_);
  gates_.resize(places_.size());
  gate_refused_.resize(places_.size());
  empty_view_.assign(uavs_.size(), 0);
}

bool Simulator::through_gateway(RegionId gateway, UavStateMsg s, uint32_t tick, CarriedDeposits* carried) {
  // As the place agent's take_home_states (core::PlaceIntake::judge_state).
  const IntakeRules rules{geo_, places_.front()->layer_count(), traits_.layer_ranges, scenario_.uavs};
  auto it = accepted_.find({gateway, s.uav});
  const UavStateMsg* before = it == accepted_.end() ? nullptr : &it->second;
  const auto judged = gates_[gateway].judge(s, before, uav_start(scenario_, traits_, s.uav), traits_.max_step,
                                            lockstep_tick_ceiling(tick), rules);
  if (carried != nullptr) *carried = carried_deposits(judged);
  if (judged.refused_motion) {
    if (!judged.copy) gate_refused_[gateway].add(Refusal::ImplausibleState);
    empty_view_[s.uav] = 1;
    recorder_.on_uav_state(refused_answer(s));
    return false;
  }
  if (!judged.verdict.taken()) {
    // Malformed (a policy that reports a position off the map): the
    // recorder rejects it too.
    recorder_.on_uav_state(s);
    return false;
  }
  accepted_[{gateway, s.uav}] = s;
  last_accepted_[s.uav] = s;
  recorder_.on_uav_state(s);
  return true;
}

HealthMsg Simulator::health_of(const PlaceCore& p, uint32_t tick, bool final) const {
  const auto& l = p.ledger();
  HealthMsg h{p.region(), tick, 0.0F, l.received, l.applied, l.rejected(), 0, final};
  RefusalCounts all = l.refused;
  const RefusalCounts& gate = gate_refused_[p.region()];
  for (std::size_t i = 0; i < kRefusalCount; ++i) all.add(static_cast<Refusal>(i), gate.n[i]);
  h.refused = all.n;
  return h;
}

Result<std::vector<std::string>> Simulator::set_faults(const FaultSchedule& schedule, bool standby) {
  const auto regions = static_cast<uint32_t>(places_.size());
  if (auto err = check_fault_schedule(schedule, scenario_.uavs, regions, true)) return Error{*err};
  std::vector<std::string> notes;
  for (const FaultEvent& e : schedule.events) {
    for (const FaultTarget& t : e.targets) {
      if (t.role == "ground" && (e.action == FaultAction::Kill || e.action == FaultAction::Restart)) {
        return Error{"'" + e.text + "': the simulator has no ground station to " + to_string(e.action) +
                     " (in a lockstep run it conducts the ticks: its death ends the run)"};
      }
    }
    if (e.action == FaultAction::Restart) {
      // A restarted process is down for a wall-clock time while a lockstep
      // run goes on without it: how many ticks it misses is not defined.
      return Error{"'" + e.text +
                   "': the simulator cannot restart a process (its down time is wall-clock time, "
                   "not ticks); use kill, or pheromesh run --clock lockstep"};
    }
    if (e.action == FaultAction::Stop || e.action == FaultAction::Partition || e.action == FaultAction::Loss) {
      notes.push_back("'" + e.text + "': does not change simulated numbers (a lockstep run only becomes slower)");
    }
  }
  uav_kill_.clear();
  region_kill_.clear();
  standby_.clear();
  for (const auto& [u, k] : schedule.uav_kills()) uav_kill_[u] = k;
  for (const auto& [r, k] : schedule.place_kills()) {
    const bool covered =
        // Captured by copy: clang before 16 cannot capture structured
        // bindings, and the fuzz tree (docs/fuzzing.md) is built with clang 14.
        standby || std::any_of(schedule.events.begin(), schedule.events.end(), [r = r, k = k](const FaultEvent& e) {
          return e.action == FaultAction::Standby && e.at_tick && *e.at_tick < k &&
                 std::find(e.targets.begin(), e.targets.end(), FaultTarget{"place", r}) != e.targets.end();
        });
    // A place agent a standby replaces is still a killed process (metrics.json
    // counts it), but its region lives on.
    region_kill_[static_cast<RegionId>(r)] = k;
    if (covered) {
      notes.push_back("kill place:" + std::to_string(r) + " @" + std::to_string(k) +
                      "t: a standby place agent takes over; the simulated numbers do not change");
      standby_.insert(static_cast<RegionId>(r));
    }
  }
  faults_ = schedule;
  standby_all_ = standby;
  fault_notes_ = notes;
  return notes;
}

Result<std::vector<std::string>> Simulator::add_faults(const FaultSchedule& more) {
  if (finished_ || done()) {
    return Error{"the run has ended (its last tick, " + std::to_string(scenario_.ticks) + ", has run): no more faults"};
  }
  const auto regions = static_cast<uint32_t>(places_.size());
  if (auto err = check_fault_schedule(more, scenario_.uavs, regions, true)) return Error{*err};
  for (const FaultEvent& e : more.events) {
    if (*e.at_tick < next_tick_) {
      return Error{"'" + e.text + "': tick " + std::to_string(*e.at_tick) + " has already run (the next tick is " +
                   std::to_string(next_tick_) + ")"};
    }
    if (e.action != FaultAction::Kill) continue;
    for (const FaultTarget& t : e.targets) {
      std::optional<uint32_t> killed;  // the tick it died at, if it has
      if (t.role == "uav" && uav_kill_.contains(t.index)) killed = uav_kill_.at(t.index);
      if (t.role == "place" && region_kill_.contains(static_cast<RegionId>(t.index))) {
        killed = region_kill_.at(static_cast<RegionId>(t.index));
      }
      if (killed && *killed < next_tick_) {
        return Error{"'" + e.text + "': " + t.role + ":" + std::to_string(t.index) +
                     " is already dead (killed at tick " + std::to_string(*killed) + ")"};
      }
    }
  }
  FaultSchedule merged = faults_;
  merge_fault_schedules(merged, more);
  std::vector<std::string> before = fault_notes_;
  auto all = set_faults(merged, standby_all_.value_or(scenario_.standby));
  if (!all) return all.error();
  // The notes of the new events: all of them but those already given.
  std::vector<std::string> added;
  for (const std::string& n : all.value()) {
    auto it = std::find(before.begin(), before.end(), n);
    if (it != before.end()) {
      before.erase(it);
    } else {
      added.push_back(n);
    }
  }
  return added;
}

std::optional<uint32_t> Simulator::uav_kill_tick(uint32_t u) const {
  auto it = uav_kill_.find(u);
  return it == uav_kill_.end() ? std::nullopt : std::optional<uint32_t>(it->second);
}

std::optional<uint32_t> Simulator::region_kill_tick(RegionId r) const {
  auto it = region_kill_.find(r);
  if (it == region_kill_.end() || standby_.contains(r)) return std::nullopt;
  return it->second;
}

bool Simulator::uav_gone(uint32_t u, uint32_t tick) const {
  if (uav_kill_.empty()) return false;
  auto it = uav_kill_.find(u);
  return it != uav_kill_.end() && tick >= it->second;
}

bool Simulator::region_dead(RegionId r, uint32_t tick) const {
  if (region_kill_.empty()) return false;
  auto it = region_kill_.find(r);
  return it != region_kill_.end() && tick >= it->second && !standby_.contains(r);
}

void Simulator::step(uint32_t tick) {
  note_kills(tick);
  uav_phase(tick);
  place_phase(tick);
  publish_tick(tick);
  next_tick_ = tick + 1;
}

void Simulator::note_kills(uint32_t tick) {
  // Kills that take effect at this tick, for the metrics.
  for (const auto& [u, k] : uav_kill_) {
    if (k != tick) continue;
    recorder_.on_uav_killed();
    if (tick > 0) recorder_.on_uav_departed(u);  // one that never flew has no status to end
  }
  for (const auto& [r, k] : region_kill_) {
    if (k != tick) continue;
    const bool frozen = !standby_.contains(r);
    recorder_.on_place_killed(frozen);
    if (frozen) {
      // Its last health record: the ledger as it stopped.
      recorder_.on_health(health_of(*places_[r], tick == 0 ? 0 : tick - 1, false));
    }
  }
}

void Simulator::uav_phase(uint32_t tick) {
  // UAV phase: every UAV sees the tiles of its neighbourhood as the place
  // agents published them at the end of tick k-1 (nothing at tick 0, as no
  // place agent has ticked yet).
  // The same holds for the states of the UAVs over those tiles and for the
  // broadcasts: those of tick k-1.
  UavCore::Output out;
  std::vector<UavStateMsg> states;
  std::vector<BroadcastMsg> broadcasts;
  for (std::size_t i = 0; i < uavs_.size(); ++i) {
    if (uav_gone(static_cast<uint32_t>(i), tick)) continue;
    show_view(i, tick);
    fly_uav(i, tick, out, states, broadcasts);
  }
  states_by_tile_.clear();
  // A policy that reads no neighbours is shown none (PolicyTraits), as a
  // place agent composes its views.
  if (!traits_.reads_neighbours) states.clear();
  for (const UavStateMsg& s : states) {
    const TileCoord t = geo_.tile_of(state_cell(s));
    states_by_tile_[{t.tx, t.ty}].push_back(s);
  }
  broadcasts_ = std::move(broadcasts);
}

void Simulator::show_view(std::size_t i, uint32_t tick) {
  const auto id = static_cast<uint32_t>(i);
  const auto regions = static_cast<uint32_t>(places_.size());
  UavCore& u = *uavs_[i];
  // The view of place tick k-1 comes from the UAV's gateway then (its home,
  // else its backup): empty if both were dead.
  const auto dead_at = [&](uint32_t k) { return [this, k](RegionId r) { return region_dead(r, k); }; };
  const bool blind = tick > 0 && !gateway_region(id, regions, dead_at(tick - 1));
  const bool empty_view = std::exchange(empty_view_[i], uint8_t{0}) != 0;
  if (tick == 0) return;
  if (!blind && empty_view) {
    // Its state of tick k-1 was refused: its gateway sent an empty view.
    u.begin_view();
  } else if (!blind) {
    u.begin_view();
    for (const TileCoord& t : u.neighbourhood()) {
      if (const std::vector<TileMsg>* layers = published_tile(t)) {
        for (const TileMsg& m : *layers) u.receive_tile(m);
        tile_samples_[i] += layers->size();
      }
      auto st = states_by_tile_.find({t.tx, t.ty});
      if (st != states_by_tile_.end()) {
        for (const UavStateMsg& s : st->second) u.receive_neighbour(s);
      }
    }
  }
  for (const BroadcastMsg& b : broadcasts_) u.receive_broadcast(b);
}

void Simulator::fly_uav(std::size_t i, uint32_t tick, UavCore::Output& out, std::vector<UavStateMsg>& states,
                        std::vector<BroadcastMsg>& broadcasts) {
  const auto id = static_cast<uint32_t>(i);
  const auto regions = static_cast<uint32_t>(places_.size());
  uavs_[i]->step(tick, out);
  ++uav_steps_;
  // The gateway publishes this state with its field of tick k; with no
  // live gateway nobody does.
  const auto gateway = gateway_region(id, regions, [this, tick](RegionId r) { return region_dead(r, tick); });
  const bool cut_off = !gateway;
  if (out.broadcast) broadcasts.push_back(*out.broadcast);
  deposits_sent_[i] += out.deposits.size();
  for (const DetectionMsg& d : out.detections) recorder_.on_detection(d);
  out.state.deposits_sent = deposits_sent_[i];
  out.state.tile_samples_received = tile_samples_[i];
  CarriedDeposits carried = CarriedDeposits::Judge;
  if (cut_off) {
    recorder_.on_uav_state(out.state);  // heard, though no view shows it
  } else if (through_gateway(*gateway, out.state, tick, &carried)) {
    states.push_back(out.state);
  }
  if (carried == CarriedDeposits::Reject) {
    // Its gateway refused its state: it applies and forwards none of the
    // deposits the state carried, as the place agents (core/intake.hpp).
    places_[*gateway]->reject(out.deposits, kRejectedWithState);
    gate_refused_[*gateway].add(Refusal::RefusedStateDeposit, static_cast<uint32_t>(out.deposits.size()));
    return;
  }
  for (const DepositMsg& d : out.deposits) {
    // Lost (no place agent to forward or apply it): RunRecorder::deposits_lost
    // counts it, as sent and never received.
    if (!cut_off && !region_dead(d.region, tick)) inbox_[d.region].push_back(d);
  }
}

void Simulator::place_phase(uint32_t tick) {
  // Place phase: deposits of tick k, rings of tick k, update, tiles of tick k.
  // A dead region does none of it: its last ring stays what its neighbours'
  // diffusion uses; its tiles are in no view from now on.
  std::vector<TargetEventMsg> events;
  std::vector<HaloMsg> rings;
  rings.reserve(places_.size());
  for (std::size_t r = 0; r < places_.size(); ++r) {
    const auto region = static_cast<RegionId>(r);
    if (region_dead(region, tick)) {
      // Its ring of its last tick (none if it was killed before it ever
      // ticked: its neighbours' halo stays 0).
      rings.push_back(last_rings_[r]);
      continue;
    }
    // Each deposit where its UAV can have put it (as the place agents judge it).
    const PlaceCore::DepositReach reach = [this](const DepositMsg& d) {
      auto it = last_accepted_.find(d.uav);
      return check_deposit_reach(d, it == last_accepted_.end() ? nullptr : &it->second,
                                 uav_start(scenario_, traits_, d.uav), traits_.max_step, traits_.deposit_reach);
    };
    HaloRing ring = places_[r]->begin_tick(inbox_[r], tick, events, nullptr, &reach);
    rings.push_back({region, tick, std::move(ring.target), std::move(ring.obstacle)});
    inbox_[r].clear();
  }
  for (std::size_t r = 0; r < places_.size(); ++r) {
    if (region_dead(static_cast<RegionId>(r), tick)) continue;
    PlaceCore& p = *places_[r];
    for (RegionId n : p.neighbours()) p.accept_halo(rings[n]);
    p.finish_tick();
  }
  last_rings_ = std::move(rings);
  for (const auto& e : events) recorder_.on_target_event(e);
}

void Simulator::publish_tick(uint32_t tick) {
  // The tiles of tick k, built when read (published_tile). A dead region's
  // tiles are in no view (its region is dark; core/faults.hpp).
  tiles_.clear();
  tiles_complete_ = false;
  tiles_tick_ = tick;
  tiles_live_.assign(places_.size(), 0);
  for (std::size_t r = 0; r < places_.size(); ++r) tiles_live_[r] = region_dead(static_cast<RegionId>(r), tick) ? 0 : 1;
  // Every live place agent's health of this tick, as a lockstep place agent
  // publishes it after its place phase (the per-tick ledger of series.csv).
  for (const auto& p : places_) {
    if (region_dead(p->region(), tick)) continue;
    recorder_.on_health(health_of(*p, tick, false));
  }
}

const std::vector<TileMsg>* Simulator::published_tile(TileCoord t) const {
  if (!tiles_tick_ || !geo_.valid_tile(t)) return nullptr;
  const auto key = std::make_pair(t.tx, t.ty);
  if (auto it = tiles_.find(key); it != tiles_.end()) return &it->second;
  const RegionId r = geo_.region_of_tile(t);
  if (tiles_live_[r] == 0 || tiles_complete_) return nullptr;
  // The place agents' fields do not change between their place phase and the
  // next one, so a tile built now is the tile they published then.
  std::vector<TileMsg> layers;
  places_[r]->tile(t, *tiles_tick_, layers);
  return &tiles_.emplace(key, std::move(layers)).first->second;
}

const std::map<std::pair<int32_t, int32_t>, std::vector<TileMsg>>& Simulator::tiles() const {
  if (!tiles_complete_ && tiles_tick_) {
    for (std::size_t r = 0; r < places_.size(); ++r) {
      if (tiles_live_[r] == 0) continue;
      for (const TileCoord& t : places_[r]->owned_tiles()) (void)published_tile(t);
    }
    tiles_complete_ = true;
  }
  return tiles_;
}

void Simulator::run(const std::function<void(uint32_t)>& on_tick) {
  while (!done()) {
    const uint32_t k = next_tick_;
    advance();
    if (on_tick) on_tick(k);
  }
  finish();
}

bool Simulator::advance() {
  if (finished_ || done()) return false;
  step(next_tick_);
  return true;
}

bool Simulator::finish() {
  if (finished_ || !done()) return false;
  finished_ = true;
  // The final accounting, as the place agents' last health records carry it
  // (a dead region's stays the one recorded when it died).
  for (const auto& p : places_) {
    if (region_dead(p->region(), scenario_.ticks)) continue;
    recorder_.on_health(health_of(*p, scenario_.ticks, true));
  }
  for (std::size_t i = 0; i < uavs_.size(); ++i) {
    const auto id = static_cast<uint32_t>(i);
    if (uav_gone(id, scenario_.ticks)) continue;  // its last state stays the last it sent
    UavStateMsg s = uavs_[i]->last_state();
    s.tick = scenario_.ticks;
    s.deposits_sent = deposits_sent_[i];
    s.tile_samples_received = tile_samples_[i];
    s.finished = true;
    // Through its gateway as every state (a copy of a refused one is
    // answered again, not counted).
    const auto dead_at_end = [this](RegionId r) { return region_dead(r, scenario_.ticks); };
    const auto gateway = gateway_region(id, static_cast<uint32_t>(places_.size()), dead_at_end);
    if (gateway) {
      (void)through_gateway(*gateway, s, scenario_.ticks);
    } else {
      recorder_.on_uav_state(s);
    }
  }
  recorder_.set_field_summary(field_summary(scenario_, [this](int layer, Cell c) { return field_value(layer, c); }));
  return true;
}

float Simulator::field_value(int layer, Cell c) const { return places_[geo_.region_of(c)]->value(layer, c); }

bool Simulator::gather_layer(int layer, std::span<float> out) const {
  const auto width = static_cast<std::size_t>(geo_.width());
  if (layer < 0 || layer >= layer_count() || out.size() != width * static_cast<std::size_t>(geo_.height()))
    return false;
  for (std::size_t r = 0; r < places_.size(); ++r) {
    const Rect rect = geo_.region_rect(static_cast<RegionId>(r));
    const PlaceCore& p = *places_[r];
    for (int32_t y = rect.y0; y < rect.y0 + rect.h; ++y) {
      for (int32_t x = rect.x0; x < rect.x0 + rect.w; ++x) {
        out[static_cast<std::size_t>(y) * width + static_cast<std::size_t>(x)] = p.value(layer, Cell{x, y});
      }
    }
  }
  return true;
}

int Simulator::layer_count() const { return places_.front()->layer_count(); }

std::vector<std::string> max_step_trial(ScenarioConfig scenario, uint32_t ticks) {
  scenario.ticks = std::min(scenario.ticks, ticks);
  scenario.faults = {};
  std::vector<std::string> out;
  try {
    Simulator sim(std::move(scenario));
    sim.run();
    const RunRecorder& r = sim.recorder();
    for (const auto& [uav, refused] : r.refused_states()) {
      out.push_back(describe_first_refusal(refused, uav, r.max_step()) + "; " + std::to_string(refused.count) +
                    " of its states refused in a trial of " + std::to_string(sim.scenario().ticks) + " ticks");
    }
  } catch (const std::exception& e) {
    out.push_back(std::string("the trial of max_step could not fly the policy: ") + e.what());
  }
  return out;
}

}  // namespace pheromesh::core
