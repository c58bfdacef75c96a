#include "pheromesh/console/mavlink_replay.hpp"

#include <algorithm>
#include <string>

namespace pheromesh::console {

namespace ml = pheromesh::mavlink;
using Clock = MavlinkReplay::Clock;
using Kind = IntakeNote::Kind;
using Level = IntakeNote::Level;

namespace {

std::string str(uint32_t v) { return std::to_string(v); }

std::size_t found(const std::vector<TargetView>& targets) {
  return static_cast<std::size_t>(std::count_if(
      targets.begin(), targets.end(), [](const TargetView& t) { return t.status != TargetStatus::NotFound; }));
}

}  // namespace

MavlinkRun mavlink_run_of(const Recording& rec) {
  MavlinkRun run;
  run.geo = rec.info.geo.value_or(core::GeoFrame{});
  run.tick_rate_hz = rec.info.tick_rate_hz;
  run.regions = static_cast<uint32_t>(rec.info.regions.size());
  run.targets = rec.frames.empty() ? 0 : rec.frames.front().targets.size();
  return run;
}

MavlinkReplay::MavlinkReplay(const Recording& rec, double rate_hz, Clock::time_point start)
    : rec_(rec), feed_(mavlink_run_of(rec), rate_hz, start), state_(initial_state(rec.info)), last_(start) {}

std::vector<std::vector<uint8_t>> MavlinkReplay::due(Clock::time_point now) {
  advance(now);
  feed_.set_paused(paused_ || state_.paused);
  return feed_.due(swarm(), now);
}

uint8_t MavlinkReplay::command(const mavlink::CommandGate::Command& c, Clock::time_point now) {
  using A = mavlink::CommandGate::Action;
  if (c.action != A::Pause && c.action != A::Resume) return ml::kResultUnsupported;
  advance(now);  // the playback up to now counts; from now it stands or runs
  paused_ = c.action == A::Pause;
  return ml::kResultAccepted;
}

void MavlinkReplay::advance(Clock::time_point now) {
  if (now > last_) {
    if (!paused_) played_ += now - last_;
    last_ = now;
  }
  if (rec_.frames.empty()) return;
  const double until = rec_.frames.front().t_s + played_s();
  // The first frame at once: the stream starts with the recording's first state.
  while (next_ < rec_.frames.size() && (next_ == 0 || rec_.frames[next_].t_s <= until)) play(rec_.frames[next_++]);
}

void MavlinkReplay::play(const Frame& f) {
  note_uavs(f);
  note_regions(f);
  note_targets(f);
  for (const UavView& u : f.uavs) {
    auto [it, fresh] = motion_.try_emplace(u.id, Motion{u.tick, u.x, u.y, 0, 0});
    Motion& m = it->second;
    if (!fresh && u.tick > m.tick) {
      const double ticks = u.tick - m.tick;
      m = {u.tick, u.x, u.y, (u.x - m.x) / ticks, (u.y - m.y) / ticks};
    }
  }
  apply(state_, f);
}

// The ground station's own log lines of a loss and a return (ground_intake.cpp).
void MavlinkReplay::note_uavs(const Frame& f) {
  for (const UavView& u : f.uavs) {
    const auto old = state_.uavs.find(u.id);
    if (old == state_.uavs.end()) continue;
    const bool was_dead = old->second.liveness == Liveness::Dead, dead = u.liveness == Liveness::Dead;
    if (!was_dead && dead) {
      feed_.note(
          {Kind::UavLost, Level::Warn, "uav " + str(u.id) + " lost (liveliness) at tick " + str(old->second.tick)});
    } else if (was_dead && !dead && u.liveness != Liveness::Finished) {
      feed_.note({Kind::UavBack, Level::Info, "uav " + str(u.id) + " is back at tick " + str(u.tick)});
    }
  }
}

void MavlinkReplay::note_regions(const Frame& f) {
  for (const RegionView& r : f.regions) {
    if (r.id >= state_.regions.size()) continue;
    const bool was_dead = state_.regions[r.id].liveness == Liveness::Dead, dead = r.liveness == Liveness::Dead;
    // A region is Dead until its first health: only one seen alive is lost.
    if (!was_dead && dead && regions_seen_.count(r.id) > 0) {
      feed_.note({Kind::PlaceLost, Level::Warn, "place agent " + str(r.id) + " lost (liveliness)"});
    } else if (was_dead && !dead && regions_seen_.count(r.id) > 0) {
      feed_.note({Kind::PlaceBack, Level::Warn, "place agent " + str(r.id) + " is back at tick " + str(r.tick)});
    }
    if (!dead) regions_seen_.insert(r.id);
  }
}

void MavlinkReplay::note_targets(const Frame& f) {
  const std::size_t total = f.targets.size();
  std::size_t now_found = found(state_.targets);
  for (std::size_t k = 0; k < total; ++k) {
    const TargetView& t = f.targets[k];
    const bool was_found = k < state_.targets.size() && state_.targets[k].status != TargetStatus::NotFound;
    if (was_found || t.status == TargetStatus::NotFound) continue;
    ++now_found;
    feed_.note({Kind::TargetAcquired, Level::Info,
                "target " + std::to_string(k) + " at (" + std::to_string(t.cell.x) + "," + std::to_string(t.cell.y) +
                    ") first acquired by uav " + std::to_string(t.found_by) + " at tick " + str(t.found_tick) + " (" +
                    std::to_string(now_found) + "/" + std::to_string(total) + ")"});
  }
}

MavlinkSwarm MavlinkReplay::swarm() const {
  MavlinkSwarm s;
  for (const auto& [id, u] : state_.uavs) {
    const bool dead = u.liveness == Liveness::Dead;
    s.uavs_lost += dead ? 1U : 0U;
    const auto m = motion_.find(id);
    const double vx = m == motion_.end() ? 0 : m->second.vx, vy = m == motion_.end() ? 0 : m->second.vy;
    // A paused playback stands still, as a paused swarm does.
    const bool still = paused_ || u.liveness == Liveness::Finished;
    s.uavs.push_back({id, u.tick, u.x, u.y, still ? 0 : vx, still ? 0 : vy, !dead, u.liveness == Liveness::Finished});
  }
  for (const uint32_t r : regions_seen_) s.places_lost += state_.regions[r].liveness == Liveness::Dead ? 1U : 0U;
  s.targets_found = found(state_.targets);
  return s;
}

}  // namespace pheromesh::console
