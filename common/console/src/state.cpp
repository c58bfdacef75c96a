#include "pheromesh/console/state.hpp"

#include <cmath>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"

namespace pheromesh::console {

const char* to_string(Liveness l) {
  switch (l) {
    case Liveness::Alive: return "alive";
    case Liveness::Stale: return "stale";
    case Liveness::Dead: return "dead";
    case Liveness::Finished: return "finished";
  }
  return "dead";
}

const char* to_string(TargetStatus s) {
  switch (s) {
    case TargetStatus::NotFound: return "not_found";
    case TargetStatus::Found: return "found";
    case TargetStatus::RevisitDue: return "revisit_due";
  }
  return "not_found";
}

ConsoleInfo console_info_of(const core::ScenarioConfig& s) {
  const core::MapGeometry geo = s.geometry();
  const core::PolicyTraits traits = core::policy_traits(s);
  ConsoleInfo info;
  info.scenario_name = s.name;
  info.scenario_path = s.source_path;
  info.policy = s.policy;
  info.width = geo.width();
  info.height = geo.height();
  info.tile_size = geo.tile_size();
  for (core::RegionId r = 0; r < geo.region_count(); ++r) info.regions.push_back(geo.region_rect(r));
  info.layers = traits.layers;
  info.tick_rate_hz = s.tick_rate_hz;
  info.ticks = s.ticks;
  info.uavs_expected = s.uavs;
  info.sensor_radius = traits.sensor_radius;
  info.geo = s.geo;
  return info;
}

ConsoleState initial_state(const ConsoleInfo& info) {
  ConsoleState s;
  s.layers.resize(info.layers.size());
  s.regions.resize(info.regions.size());
  for (std::size_t r = 0; r < s.regions.size(); ++r) s.regions[r].id = static_cast<uint32_t>(r);
  return s;
}

void apply(ConsoleState& s, const Frame& f) {
  s.version = f.version;
  s.t_s = f.t_s;
  s.tick = f.tick;
  s.paused = f.paused;
  for (const auto& [layer, scale] : f.scales) {
    if (layer < s.layers.size()) s.layers[layer].scale = scale;
  }
  for (const auto& d : f.tiles) {
    if (d.layer >= s.layers.size()) continue;
    TileImage& t = s.layers[d.layer].tiles[{d.tx, d.ty}];
    t.rect = d.rect;
    t.tick = d.tick;
    t.q = d.q;
    t.version = f.version;
  }
  // UAVs: the frame lists every UAV; tracks are extended here, decimated.
  for (const auto& u : f.uavs) {
    UavView& v = s.uavs[u.id];
    // Back from the dead (a restarted process starts at its start cell): a
    // new track, not a line across the map.
    if (v.liveness == Liveness::Dead && u.liveness != Liveness::Dead) v.track.clear();
    std::deque<TrackPoint> track = std::move(v.track);
    v = u;
    v.track = std::move(track);
    const bool moved = v.track.empty() || std::hypot(v.track.back().x - u.x, v.track.back().y - u.y) >= kTrackStep;
    if (moved && u.liveness != Liveness::Dead) {
      v.track.push_back({static_cast<float>(u.x), static_cast<float>(u.y), f.version});
      while (v.track.size() > kTrackPoints) v.track.pop_front();
    }
  }
  s.regions = f.regions;
  s.targets = f.targets;
  s.obstacles = f.obstacles;
  if (f.series) {
    s.series.push_back(*f.series);
    s.series.back().version = f.version;
    if (s.series.size() > kSeriesPoints) s.series.erase(s.series.begin());
  }
  for (const auto& c : f.commands) {
    s.commands.push_back(c);
    s.commands.back().version = f.version;
    while (s.commands.size() > kCommandLog) s.commands.pop_front();
  }
}

}  // namespace pheromesh::console
