#include "pheromesh/console/ground_intake.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <limits>
#include <type_traits>
#include <utility>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/uav_core.hpp"

namespace pheromesh::console {

namespace {

using Kind = IntakeNote::Kind;
using Level = IntakeNote::Level;

// The shortest text that reads back as `v` ("2.5", "3"), as the log's {} prints it.
void append(std::string& out, double v) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  out.append(buf.data(), r.ptr);
}
void append(std::string& out, const std::string& s) { out += s; }
void append(std::string& out, const char* s) { out += s; }
template <typename T>
requires std::is_integral_v<T>
void append(std::string& out, T v) { out += std::to_string(v); }

template <typename... Parts>
std::string text(const Parts&... parts) {
  std::string out;
  (append(out, parts), ...);
  return out;
}

}  // namespace

void GroundSamples::clear() {
  states.clear();
  broadcasts.clear();
  departed_uavs.clear();
  detections.clear();
  target_events.clear();
  healths.clear();
  fields.clear();
  tiles.clear();
  departed_places.clear();
  phase_dones.clear();
}

GroundIntake::GroundIntake(const core::ScenarioConfig& scenario, Parts parts, Standby standby,
                           std::chrono::milliseconds lease, Pace pace)
    : p_(parts),
      standby_(standby),
      geo_(scenario.geometry()),
      swarm_(scenario.uavs),
      layers_(static_cast<int>(core::policy_traits(scenario).layers.size())),
      layer_ranges_(core::policy_traits(scenario).layer_ranges),
      lease_(lease),
      pace_(pace),
      places_(place_takeover(lease, pace)),
      names_{scenario.uavs, geo_.region_count(), core::replicas_of(standby == Standby::Hot)} {}

GroundIntake::Clock::duration GroundIntake::place_takeover(std::chrono::milliseconds lease, Pace pace) {
  // A place agent writes its health every half second (realtime) or every
  // tick (lockstep, where a tick under packet loss takes seconds): silent
  // for two leases (six in lockstep), it is dead, and a process started
  // again for its region takes the id - sooner, by its later life.
  using std::chrono::seconds;
  if (pace == Pace::Lockstep) return std::max<Clock::duration>(seconds(10), 6 * lease);
  return std::max<Clock::duration>(seconds(2), 2 * lease);
}

GroundIntake::Notes GroundIntake::take(GroundSamples& in, uint32_t tick_ceiling, Clock::time_point now) {
  p_.rec.set_tick_ceiling(tick_ceiling);
  vouch(in, now);
  on_states(in.states, now);
  on_broadcasts(in.broadcasts, now);
  on_departed_uavs(in.departed_uavs, now);
  for (const auto& d : in.detections) p_.rec.on_detection(d);
  note_acquisitions();
  on_target_events(in.target_events);
  on_healths(in.healths, now);
  on_fields(in.fields, in.tiles, tick_ceiling);
  on_tiles(in.tiles, tick_ceiling);
  on_departed_places(in.departed_places, now);
  on_phase_dones(in.phase_dones, now);
  judge_departures(now, /*all=*/false);
  return std::exchange(notes_, {});
}

std::size_t GroundIntake::parked() const {
  return parked_states_.size() + parked_departures_.size() + parked_broadcasts_.size() + parked_detections_.size() +
         parked_events_.size() + parked_fields_.size() + parked_tiles_.size();
}

void GroundIntake::vouch(GroundSamples& in, Clock::time_point now) {
  // A place agent departed: a process started again for it may claim its id.
  for (uint32_t id : in.departed_places) places_.departed(id);
  for (const auto& h : in.healths) places_.heard(core::place_id(h.region, h.replica), h.participant, now);
  // Only a place agent the run has, and only from the process that holds
  // its id (core::judge_place_sample): a health under another id would
  // make its process a place agent for every relay and put its counters
  // into metrics.json.
  std::erase_if(in.healths, [&](const core::HealthMsg& h) {
    const uint32_t id = core::place_id(h.region, h.replica);
    const auto latest = p_.rec.replica_health().find(id);
    const bool new_life = latest != p_.rec.replica_health().end() && h.life > latest->second.life;
    const auto v =
        core::judge_place_sample(places_, h.region, h.replica, h.participant, now, names_, new_life, "a health");
    if (v.taken()) return false;
    refuse(v.refusal, v.reason);
    return true;
  });
  gate(parked_states_, in.states, now);
  gate(parked_departures_, in.departed_uavs, now);
  gate(parked_broadcasts_, in.broadcasts, now);
  gate(parked_detections_, in.detections, now);
  gate(parked_events_, in.target_events, now);
  gate(parked_fields_, in.fields, now);
  gate(parked_tiles_, in.tiles, now);
}

template <typename T>
const char* GroundIntake::relay_name() {
  if constexpr (std::is_same_v<T, core::UavStateMsg>) return "a relayed uav state";
  if constexpr (std::is_same_v<T, core::UavDeparture>) return "a relayed departure";
  if constexpr (std::is_same_v<T, core::BroadcastMsg>) return "a relayed broadcast";
  if constexpr (std::is_same_v<T, core::DetectionMsg>) return "a relayed detection";
  if constexpr (std::is_same_v<T, core::TargetEventMsg>) return "a target event";
  if constexpr (std::is_same_v<T, core::FieldMsg>) return "a field chunk";
  return "a tile";
}

template <typename T>
void GroundIntake::refuse_parked(core::Parked<T>& parked) {
  for (const auto& m : parked.take_all()) refuse_unvouched(relay_name<T>(), m.participant);
}

template <typename T>
void GroundIntake::gate(core::Parked<T>& parked, std::vector<T>& in, Clock::time_point now) {
  const char* what = relay_name<T>();
  // A malformed sample is dropped and counted as such, whoever wrote it
  // (on_states, on_broadcasts, on_tiles); the others by who wrote them.
  const auto malformed = [&](const T& m) {
    if constexpr (std::is_same_v<T, core::UavStateMsg>) return core::check_uav_state(m, geo_).has_value();
    if constexpr (std::is_same_v<T, core::BroadcastMsg>) return core::check_broadcast(m).has_value();
    if constexpr (std::is_same_v<T, core::TileMsg>) return core::check_tile(m, geo_, layers_).has_value();
    return false;
  };
  const auto vouched = [&](const T& m) { return places_.vouched(m.participant) || malformed(m); };
  std::vector<T> kept, expired;
  if (!parked.empty()) parked.sweep(now, places_.park_for(), vouched, kept, expired);
  for (const auto& m : expired) refuse_unvouched(what, m.participant);
  if (kept.empty() && std::all_of(in.begin(), in.end(), vouched)) return;  // the common case: nothing moves
  for (auto& m : in) {
    if (vouched(m)) {
      kept.push_back(std::move(m));
    } else if (auto out = parked.park(std::move(m), now)) {
      refuse_unvouched(what, out->participant);
    }
  }
  in.swap(kept);
}

void GroundIntake::refuse_unvouched(const char* what, uint64_t participant) {
  refuse(core::Refusal::ForeignWriter,
         text(what, " from a process never heard as a place agent (participant ", participant, ")"));
}

bool GroundIntake::speaks_for_region(core::RegionId r, uint64_t participant) const {
  const uint16_t replicas = standby_ == Standby::Hot ? 2 : 1;
  for (uint16_t k = 0; k < replicas; ++k) {
    if (places_.speaks_for(core::place_id(r, k), participant)) return true;
  }
  return false;
}

GroundIntake::Notes GroundIntake::judge_pending() {
  // The end: what still waits for its process to be heard as a place agent
  // never will be.
  refuse_parked(parked_states_);
  refuse_parked(parked_departures_);
  refuse_parked(parked_broadcasts_);
  refuse_parked(parked_detections_);
  refuse_parked(parked_events_);
  refuse_parked(parked_fields_);
  refuse_parked(parked_tiles_);
  p_.rec.judge_pending_detections();
  note_acquisitions();
  judge_departures(Clock::time_point::max(), /*all=*/true);
  if (lapses_ > 0) {
    const auto lapsed = [](const std::map<uint32_t, Liveness>& m) {
      return std::count_if(m.begin(), m.end(), [](const auto& e) { return e.second.lapse_noted; });
    };
    note(Kind::LivenessLapsed, Level::Info,
         text("liveliness lapsed ", lapses_, " times while the process was still heard (packet loss?; UAVs ",
              lapsed(uav_live_), ", place agents ", lapsed(place_live_), "); none was taken for lost"));
  }
  return std::exchange(notes_, {});
}

bool GroundIntake::heard(Who who, uint32_t id, Clock::time_point now, bool new_life) {
  Liveness& l = (who == Who::Uav ? uav_live_ : place_live_)[id];
  if (l.heard != Clock::time_point{} && now > l.heard) l.longest_silence = std::max(l.longest_silence, now - l.heard);
  l.heard = std::max(l.heard, now);
  if (l.departed) {  // heard within its wait after its departure (else judged already)
    l.departed.reset();
    if (new_life) {
      // Its next life, not the one that lapsed: that one died (killed and
      // started again), which is no packet loss.
      note_lost(who, id);
    } else {
      note_lapse(who, id);
    }
  }
  return std::exchange(l.reported_lost, false);
}

void GroundIntake::departed(Who who, uint32_t id, Clock::time_point now) {
  Liveness& l = (who == Who::Uav ? uav_live_ : place_live_)[id];
  // Judged by what comes after it only: a process cut off (a partition) or
  // killed was heard until just before, like one whose assertions were lost
  // (Fast DDS reported a partitioned UAV departed within half a lease of its
  // last state).
  if (!l.departed) {
    l.departed = now;
    pending_.emplace_back(who, id);
  }
}

void GroundIntake::note_lapse(Who who, uint32_t id) {
  ++lapses_;
  Liveness& l = (who == Who::Uav ? uav_live_ : place_live_)[id];
  if (std::exchange(l.lapse_noted, true)) return;
  note(Kind::LivenessLapsed, Level::Warn,
       text(who_text(who, id),
            ": liveliness lapsed (packet loss?), still heard; not taken for lost (further lapses are "
            "counted at the end of the run)"));
}

GroundIntake::Clock::duration GroundIntake::wait(const Liveness& l) const {
  if (pace_ == Pace::Realtime) return lease_ / 2;
  const Clock::duration floor = place_takeover(std::chrono::duration_cast<std::chrono::milliseconds>(lease_), pace_);
  return std::clamp<Clock::duration>(2 * l.longest_silence, floor, 3 * floor);
}

void GroundIntake::judge_departures(Clock::time_point now, bool all) {
  // In the order they departed.
  std::erase_if(pending_, [&](const std::pair<Who, uint32_t>& p) {
    Liveness& l = (p.first == Who::Uav ? uav_live_ : place_live_)[p.second];
    if (!l.departed) return true;  // heard since: a lapse
    if (!all && now - *l.departed <= wait(l)) return false;
    l.departed.reset();
    note_lost(p.first, p.second);
    return true;
  });
}

void GroundIntake::note_lost(Who who, uint32_t id) {
  if (who == Who::Uav) {
    auto it = p_.rec.uavs().find(id);
    const bool known = it != p_.rec.uavs().end();
    if (known && it->second.finished) return;
    uav_live_[id].reported_lost = true;
    note(Kind::UavLost, Level::Warn,
         text("uav ", id, " lost (liveliness) at tick ", known ? it->second.last.tick : 0U));
    return;
  }
  auto it = p_.rec.replica_health().find(id);
  if (it != p_.rec.replica_health().end() && it->second.finished) return;
  place_live_[id].reported_lost = true;
  const core::RegionId r = core::place_id_region(id);
  if (auto owner = p_.rec.region_owner(r)) {
    note(Kind::PlaceLost, Level::Warn,
         text(who_text(who, id), " lost (liveliness); region ", r, " is served by ",
              *owner == 0 ? std::string("its primary") : text("standby ", *owner)));
  } else {
    note(Kind::PlaceLost, Level::Warn,
         text(who_text(who, id), " lost (liveliness); region ", r,
              " has no live place agent: deposits into it are lost"));
  }
}

std::string GroundIntake::who_text(Who who, uint32_t id) const {
  if (who == Who::Uav) return text("uav ", id);
  const uint16_t replica = core::place_id_replica(id);
  const core::RegionId r = core::place_id_region(id);
  return replica > 0 ? text("standby ", replica, " of region ", r) : text("place agent ", r);
}

std::vector<uint32_t> GroundIntake::places_without_health_of(uint32_t tick) const {
  std::vector<uint32_t> missing;
  const auto& latest = p_.rec.replica_health();
  const uint16_t last_replica = standby_ == Standby::Hot ? 1 : 0;
  for (core::RegionId r = 0; r < geo_.region_count(); ++r) {
    if (p_.conductor.absent(r)) continue;
    for (uint16_t rep = 0; rep <= last_replica; ++rep) {
      const uint32_t place = core::place_id(r, rep);
      if (p_.conductor.place_gone(place)) continue;
      auto it = latest.find(place);
      if (it == latest.end() || it->second.tick < tick) missing.push_back(place);
    }
  }
  return missing;
}

std::optional<std::vector<core::RegionId>> GroundIntake::heard_places_over(Clock::time_point now,
                                                                           Clock::duration quiet) {
  const auto& heard = p_.rec.replica_health();
  const bool all_finished = !heard.empty() && std::all_of(heard.begin(), heard.end(), [&](const auto& kv) {
    return kv.second.finished || p_.rec.place_departed(kv.first);
  });
  if (!all_finished) {
    heard_places_finished_.reset();
    return std::nullopt;
  }
  if (!heard_places_finished_) heard_places_finished_ = now;
  if (now - *heard_places_finished_ <= quiet) return std::nullopt;
  std::vector<core::RegionId> never_heard;
  for (core::RegionId r = 0; r < geo_.region_count(); ++r) {
    const bool any =
        std::any_of(heard.begin(), heard.end(), [&](const auto& kv) { return core::place_id_region(kv.first) == r; });
    if (!any) never_heard.push_back(r);
  }
  return never_heard;
}

float GroundIntake::field_value(int layer, core::Cell c) const {
  const core::TileCoord t = geo_.tile_of(c);
  auto it = tiles_.find({layer, {t.tx, t.ty}});
  if (it == tiles_.end()) return std::numeric_limits<float>::quiet_NaN();
  const core::Rect r = geo_.tile_rect(t);
  const auto row = static_cast<std::size_t>(c.y - r.y0);
  const auto column = static_cast<std::size_t>(c.x - r.x0);
  return it->second.values[row * static_cast<std::size_t>(r.w) + column];
}

void GroundIntake::on_states(const std::vector<core::UavStateMsg>& states, Clock::time_point now) {
  for (const auto& s : states) {
    const uint64_t refused_before = p_.rec.refused().total();
    // A restarted UAV counts its deposits from 0 again (RunRecorder::on_uav_state).
    const bool new_life = p_.rec.starts_new_life(s);
    if (!p_.rec.on_uav_state(s)) {
      const bool refused = p_.rec.refused().total() > refused_before;  // else malformed
      if (!refused && p_.rec.samples_rejected() <= 3) {
        note(Kind::StateDropped, Level::Warn, text("dropped state of uav ", s.uav));
      } else if (refused && p_.rec.refused().total() <= 5) {
        note(Kind::StateRefused, Level::Warn,
             text("refused state of uav ", s.uav, " at tick ", s.tick, " (", s.x, ", ", s.y, "): implausible"));
      }
      continue;
    }
    const bool was_lost = heard(Who::Uav, s.uav, now, new_life);
    p_.conductor.heard_from(s.uav, now);
    if (s.implausible) note_refused_state(s);
    const bool back = s.finished      ? p_.conductor.on_uav_finished(s.uav)
                      : s.implausible ? p_.conductor.on_uav_refused(s.uav, s.tick)
                                      : p_.conductor.on_uav_state(s.uav, s.tick, geo_.tile_of(core::state_cell(s)),
                                                                  core::served_pose(s));
    if (back && was_lost && !s.finished)
      note(Kind::UavBack, Level::Info, text("uav ", s.uav, " is back at tick ", s.tick));
    p_.frames.heard_uav(s.uav, now);
    if (uncertainty_ != nullptr && !s.finished && !s.implausible) uncertainty_->observe(core::state_cell(s), s.tick);
  }
}

void GroundIntake::note_refused_state(const core::UavStateMsg& s) {
  // The first of each UAV, as its gateway refused it (the run's summary
  // says how many: core::refused_states_summary).
  const auto& all = p_.rec.refused_states();
  auto it = all.find(s.uav);
  if (it == all.end() || it->second.count != 1 || it->second.last_tick != s.tick) return;
  if (++states_refused_noted_ > 5) return;
  note(Kind::StateRefused, Level::Warn, core::describe_first_refusal(it->second, s.uav, p_.rec.max_step()));
}

void GroundIntake::on_broadcasts(const std::vector<core::BroadcastMsg>& broadcasts, Clock::time_point now) {
  for (const auto& b : broadcasts) {
    if (core::check_broadcast(b)) {
      p_.rec.count_rejected_sample();
      continue;
    }
    if (core::check_uav_id(b.uav, swarm_)) {
      refuse(core::Refusal::UnknownUav, text("a broadcast of uav ", b.uav));
      continue;
    }
    p_.conductor.on_broadcast(b.uav, b.tick);
    p_.conductor.heard_from(b.uav, now);
    (void)heard(Who::Uav, b.uav, now);
  }
}

void GroundIntake::on_departed_uavs(const std::vector<core::UavDeparture>& gone, Clock::time_point now) {
  for (const auto& d : gone) {
    const uint32_t id = d.uav;
    if (core::check_uav_id(id, swarm_)) continue;  // a forger's writer left, not a UAV
    auto it = p_.rec.uavs().find(id);
    const bool finished = it != p_.rec.uavs().end() && it->second.finished;
    // A relay that lost the UAV before its newest state (RunRecorder::on_uav_departed).
    if (!p_.rec.on_uav_departed(d)) continue;
    if (p_.conductor.on_uav_departed(id, now) && !finished) departed(Who::Uav, id, now);
  }
}

void GroundIntake::on_target_events(const std::vector<core::TargetEventMsg>& events) {
  for (const auto& e : events) {
    if (e.region < geo_.region_count() && !speaks_for_region(e.region, e.participant)) {
      refuse(core::Refusal::ForeignWriter,
             text("a target event of region ", e.region, " from another place agent's process"));
      continue;
    }
    p_.rec.on_target_event(e);
    // Shao 2020 revisits (marks.hpp).
    if (e.kind == static_cast<uint8_t>(core::TargetEventKind::RevisitDue)) p_.frames.revisit(e.cell, /*due=*/true);
    if (e.kind == static_cast<uint8_t>(core::TargetEventKind::Revisited)) p_.frames.revisit(e.cell, /*due=*/false);
  }
}

void GroundIntake::on_healths(const std::vector<core::HealthMsg>& healths, Clock::time_point now) {
  for (const auto& h : healths) {
    const auto owner_before = p_.rec.region_owner(h.region);
    const auto latest = p_.rec.replica_health().find(core::place_id(h.region, h.replica));
    const bool new_life = latest != p_.rec.replica_health().end() && h.life > latest->second.life;
    const bool was_lost = heard(Who::Place, core::place_id(h.region, h.replica), now, new_life);
    if (p_.rec.on_health(h)) {
      // Back after a lapse: in step, the conductor waits for it again
      // (whether or not its lapse was reported as a loss).
      const bool waited = standby_ == Standby::Hot && p_.conductor.on_place_back(core::place_id(h.region, h.replica));
      if (was_lost) {
        note(Kind::PlaceBack, Level::Warn,
             text("place agent ", h.region, h.replica > 0 ? text(" (standby ", h.replica, ")") : std::string(),
                  " is back at tick ", h.tick, waited ? " (in step: waited for again)" : ""));
      }
    }
    const auto owner = p_.rec.region_owner(h.region);
    if (owner_before && owner && *owner < *owner_before) {
      note(Kind::OwnerRegained, Level::Info, text("region ", h.region, ": replica ", *owner, " owns it again"));
    }
    p_.frames.heard_region(h.region, now);
    if (h.linked) p_.book.note_linked(h.region);
  }
}

void GroundIntake::on_fields(std::vector<core::FieldMsg>& fields, std::vector<core::TileMsg>& tiles, uint32_t ceiling) {
  for (auto& f : fields) {
    // A forged chunk must not enter the field nor the count of chunks the
    // last tick waits for (RunBook::holds_last_fields): one from a place
    // agent's process, but not this region's, neither.
    if (!places_.speaks_for(core::place_id(f.region, f.replica), f.participant)) {
      refuse(core::Refusal::ForeignWriter,
             text("a field chunk of ", who_text(Who::Place, core::place_id(f.region, f.replica)),
                  " from another place agent's process"));
      continue;
    }
    if (auto reason = core::check_tick_reachable(f.tick, ceiling, "field")) {
      refuse(core::Refusal::TickFarAhead, *reason);
      continue;
    }
    const auto out_of_range = std::find_if(f.tiles.begin(), f.tiles.end(),
                                           [&](const auto& t) { return core::check_tile_range(t, layer_ranges_); });
    if (out_of_range != f.tiles.end()) {
      refuse(core::Refusal::ValueOutOfRange, "a field chunk: " + *core::check_tile_range(*out_of_range, layer_ranges_));
      continue;
    }
    p_.book.on_field_chunk(f.region, f.tick, f.chunk, f.chunks);
    for (auto& t : f.tiles) {
      t.participant = f.participant;
      tiles.push_back(std::move(t));
    }
  }
}

void GroundIntake::on_tiles(std::vector<core::TileMsg>& tiles, uint32_t ceiling) {
  for (auto& t : tiles) {
    if (auto reason = core::check_tile(t, geo_, layers_)) {
      p_.rec.count_rejected_sample();
      if (p_.rec.samples_rejected() <= 3) {
        note(Kind::TileDropped, Level::Warn, text("dropped tile (", t.tile.tx, ",", t.tile.ty, "): ", *reason));
      }
      continue;
    }
    if (!speaks_for_region(geo_.region_of_tile(t.tile), t.participant)) {
      refuse(core::Refusal::ForeignWriter,
             text("a tile of region ", geo_.region_of_tile(t.tile), " from another place agent's process"));
      continue;
    }
    // Forged values must not reach the final field (plausibility.hpp).
    if (auto reason = core::check_tick_reachable(t.tick, ceiling, "tile")) {
      refuse(core::Refusal::TickFarAhead, *reason);
      continue;
    }
    if (auto reason = core::check_tile_range(t, layer_ranges_)) {
      refuse(core::Refusal::ValueOutOfRange, *reason);
      continue;
    }
    auto& slot = tiles_[{t.layer, {t.tile.tx, t.tile.ty}}];
    if (slot.values.empty() || t.tick >= slot.tick) slot = std::move(t);
  }
}

void GroundIntake::on_departed_places(const std::vector<uint32_t>& gone, Clock::time_point now) {
  for (uint32_t id : gone) {
    auto it = p_.rec.replica_health().find(id);
    const bool finished = it != p_.rec.replica_health().end() && it->second.finished;
    p_.rec.on_place_departed(id);
    if (finished) continue;
    if (standby_ == Standby::Hot) p_.conductor.on_place_departed(id);
    departed(Who::Place, id, now);
  }
}

void GroundIntake::on_phase_dones(const std::vector<core::PhaseDoneMsg>& dones, Clock::time_point now) {
  for (const auto& d : dones) {
    // Judged by who wrote it (core::judge_report): a forged report would
    // finish a phase for a process that has not, or announce deposits that
    // were never made.
    if (const auto v = core::judge_report(d, places_, names_); !v.taken()) {
      if (v.kind == core::IntakeVerdict::Kind::Drop) {
        p_.rec.count_rejected_sample();
      } else {
        refuse(v.refusal, v.reason);
      }
      continue;
    }
    p_.conductor.on_phase_done(d);
    const uint32_t id = d.process & 0xFFFFFFU;
    if (d.process >> 24U == core::kRoleUav && !core::check_uav_id(id, swarm_)) {
      p_.conductor.heard_from(id, now);
      (void)heard(Who::Uav, id, now);
    } else if (d.process >> 24U == core::kRolePlace) {
      (void)heard(Who::Place, id, now);
    }
  }
}

void GroundIntake::note_acquisitions() {
  for (const auto& d : p_.rec.take_first_acquisitions()) {
    p_.frames.target_found(d.target, d.uav, d.tick);
    note(Kind::TargetAcquired, Level::Info,
         text("target ", d.target, " at (", d.cell.x, ",", d.cell.y, ") first acquired by uav ", d.uav, " at tick ",
              d.tick, " (", p_.rec.acquisitions().found(), "/", p_.world.targets().size(), ")"));
  }
}

void GroundIntake::refuse(core::Refusal r, const std::string& what) {
  p_.rec.count_refused(r);
  if (p_.rec.refused().total() <= 5) {
    note(Kind::SampleRefused, Level::Warn, text("refused ", what, " (", core::refusal_name(r), ")"));
  }
}

void GroundIntake::note(IntakeNote::Kind kind, IntakeNote::Level level, std::string line) {
  notes_.push_back({kind, level, std::move(line)});
}

}  // namespace pheromesh::console
