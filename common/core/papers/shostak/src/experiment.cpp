// Shostak 2024 Sec. 5 experiments as a library; the loop's rules and the
// order of random draws are at the top of shostak/experiment.hpp.
#include "pheromesh/shostak/experiment.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "pheromesh/core/rng.hpp"

namespace pheromesh::core {

double shostak_explored_crossing_s(const ShostakLayerParams& params, double from, double to, double dt_s) {
  ShostakLayers layers({0, 0, 1, 1}, params);
  layers.deposit(ShostakLayer::Explored, {0, 0}, from);
  for (int k = 1; k < 100000; ++k) {
    layers.evaporate(dt_s);  // Shostak 2024 eq. (2)
    if (layers.value(ShostakLayer::Explored, {0, 0}) <= to) return k * dt_s;
  }
  return std::nan("");
}

ShostakHoverTrace shostak_hover(const ShostakLayerParams& params, double hover_s, uint32_t periods) {
  ShostakHoverTrace out;
  ShostakLayers hover({0, 0, 1, 1}, params);
  out.points.emplace_back(0.0, 0.0);
  const double dt = params.deposit_period_s;
  for (uint32_t k = 1; k <= periods; ++k) {
    const double t = k * dt;
    hover.evaporate(dt);                                       // Shostak 2024 eq. (2)
    if (t <= hover_s + 1e-9) hover.deposit_explored({0, 0});  // Shostak 2024 eq. (1)
    const double v = hover.value(ShostakLayer::Explored, {0, 0});
    if (!out.full_s && v >= params.explored_max - 1e-6) out.full_s = t;
    out.points.emplace_back(t, v);
  }
  return out;
}

namespace {

using Vec3 = Eigen::Vector3d;

struct SwarmUav {
  Vec3 pos = Vec3::Zero();
  std::optional<Vec3> waypoint;
  double heading = 0.0;  // azimuth of the last move [rad]
  Rng rng{0};
  std::optional<double> arrived_s;  // after the broadcast
  std::vector<std::pair<double, double>> track;
};

double horizontal(const Vec3& a, const Vec3& b) { return std::hypot(a.x() - b.x(), a.y() - b.y()); }

// The constants of a swarm run: the paper's parameters and the setup's geometry.
struct SwarmConstants {
  ShostakLayerParams lp;  // 5 m cells, +1 per 0.2 s, ρ = 0.05, τmax 10 / 10 / 100
  ShostakAcoParams aco;   // N = 20, d = 15 m, ψ ∈ ±30°, α = 1.5, β = 3
  ShostakAttractivenessParams attr;
  double size_m = 0.0;
  double dt = 0.0;      // one tick [s]
  double step_m = 0.0;  // flown per tick [m]
  Vec3 launch = Vec3::Zero();

  explicit SwarmConstants(const ShostakSwarmSetup& s)
      : size_m(s.cells * lp.cell_size_m),
        dt(lp.deposit_period_s),
        step_m(s.speed_mps * dt),
        launch(0.5 * size_m, 0.5 * size_m, s.altitude_m) {}
};

// The cells any UAV has been over.
struct SeenCells {
  int32_t cells;  // the map's side
  std::vector<char> seen;
  std::size_t count = 0;

  explicit SeenCells(int32_t side)
      : cells(side), seen(static_cast<std::size_t>(side) * static_cast<std::size_t>(side), 0) {}
  void mark(Cell here) {
    char& s =
        seen[static_cast<std::size_t>(here.y) * static_cast<std::size_t>(cells) + static_cast<std::size_t>(here.x)];
    if (s == 0) ++count;
    s = 1;
  }
  [[nodiscard]] double share() const { return static_cast<double>(count) / static_cast<double>(seen.size()); }
};

// The target and the obstacles, drawn from the run's scenario stream.
void draw_target_and_obstacles(ShostakSwarmRun& out, const ShostakSwarmSetup& s, const SwarmConstants& k,
                               uint64_t seed) {
  Rng world(stream_seed(seed, "scenario", 0));
  auto uniform_xy = [&](double margin) {
    return Vec3(margin + (k.size_m - 2 * margin) * world.uniform01(),
                margin + (k.size_m - 2 * margin) * world.uniform01(), 0.0);
  };
  do {
    out.target = uniform_xy(k.lp.cell_size_m);
  } while (horizontal(out.target, k.launch) < s.target_min_distance_m);
  for (uint32_t j = 0; j < s.obstacles; ++j) out.obstacles.push_back(uniform_xy(k.lp.cell_size_m));
}

std::vector<SwarmUav> launch_uavs(const ShostakSwarmSetup& s, const SwarmConstants& k, uint64_t seed) {
  std::vector<SwarmUav> uavs(s.uavs);
  for (uint32_t i = 0; i < s.uavs; ++i) {
    uavs[i].pos = k.launch;
    uavs[i].heading = shostak_dispersal_heading(i, s.uavs);  // Shostak 2024 Sec. 5: 0°/120°/240°
    uavs[i].waypoint = shostak_dispersal_waypoint(k.launch, i, s.uavs, s.dispersal_m);
    uavs[i].rng = Rng(stream_seed(seed, "uav", i));
  }
  return uavs;
}

// Shostak 2024 Sec. 3.4, Shostak 2024 Sec. 3.5: the next waypoint by roulette; η prefers the
// reported target's bearing after the broadcast, the current heading before.
void choose_waypoint(SwarmUav& u, const ShostakSwarmRun& out, const ShostakSwarmSetup& s, const SwarmConstants& k,
                     const ShostakLookup& lookup) {
  std::optional<double> preferred = u.heading;
  if (out.detect_s) preferred = std::atan2(out.target.y() - u.pos.y(), out.target.x() - u.pos.x());
  const auto choice = shostak_choose(u.pos, preferred, lookup, k.lp.cell_size_m, k.aco, k.attr, u.rng);
  if (choice) {
    Vec3 w = choice->candidate.position;
    w.z() = std::clamp(w.z(), s.min_altitude_m, s.max_altitude_m);
    u.waypoint = w;
  } else {  // every candidate off the map: head back toward the middle
    const Vec3 back = k.launch - u.pos;
    u.waypoint = u.pos + k.aco.step_m * back.normalized();
  }
}

// One tick's flight toward the waypoint; the waypoint is dropped on arrival.
void fly_toward_waypoint(SwarmUav& u, double step_m) {
  const Vec3 to = *u.waypoint - u.pos;
  if (to.norm() <= step_m) {
    u.pos = *u.waypoint;
    u.waypoint.reset();
  } else {
    u.pos += step_m * to.normalized();
  }
  if (to.head<2>().norm() > 1e-9) u.heading = std::atan2(to.y(), to.x());
}

// Shostak 2024 Sec. 5: target pheromone 100 at the target and an immediate broadcast.
void broadcast_detection(ShostakSwarmRun& out, std::vector<SwarmUav>& uavs, uint32_t detector, double t,
                         ShostakLayers& layers, const ShostakSwarmSetup& s, const SwarmConstants& k) {
  out.detect_s = t;
  out.detector = detector;
  layers.mark_target(shostak_cell_of(out.target, k.lp.cell_size_m));
  double farthest = 0.0;
  for (uint32_t j = 0; j < s.uavs; ++j) {
    if (j == detector) continue;
    uavs[j].waypoint.reset();  // the others turn toward the target at once
    farthest = std::max(farthest, horizontal(uavs[j].pos, out.target));
  }
  out.direct_s = std::max(0.0, farthest - s.converge_radius_m) / s.speed_mps;
}

// The shared state one tick of the swarm works on.
struct SwarmState {
  ShostakLayers& layers;  // the shared /swarm/pheromone_map
  const ShostakLookup& lookup;
  SeenCells& seen;
  std::vector<SwarmUav>& uavs;
};

// UAV i's tick: waypoint, flight, deposit, hazard, detection, track.
void swarm_uav_tick(ShostakSwarmRun& out, SwarmState& w, uint32_t i, int tick, double t, const ShostakSwarmSetup& s,
                    const SwarmConstants& k) {
  SwarmUav& u = w.uavs[i];
  if (!u.waypoint) choose_waypoint(u, out, s, k, w.lookup);
  fly_toward_waypoint(u, k.step_m);
  const Cell here = shostak_cell_of(u.pos, k.lp.cell_size_m);
  w.layers.deposit_explored(here);  // Shostak 2024 eq. (1), every 0.2 s
  if (Rect{0, 0, s.cells, s.cells}.contains(here)) w.seen.mark(here);
  for (const Vec3& o : out.obstacles) {
    if (horizontal(o, u.pos) <= s.lidar_range_m) w.layers.mark_hazard(here);  // Shostak 2024 Sec. 4.2
  }
  if (!out.detect_s && horizontal(out.target, u.pos) <= s.detect_radius_m) {
    broadcast_detection(out, w.uavs, i, t, w.layers, s, k);
  }
  if (tick % 5 == 0) u.track.emplace_back(u.pos.x(), u.pos.y());
}

// Whether the run ends after the tick at t: the search found nothing in time,
// every other UAV has arrived (then converge_s is set), or convergence timed out.
bool swarm_run_over(ShostakSwarmRun& out, std::vector<SwarmUav>& uavs, double t, const ShostakSwarmSetup& s) {
  if (!out.detect_s) return t >= s.search_limit_s;
  bool all = true;
  for (uint32_t j = 0; j < s.uavs; ++j) {
    if (j == out.detector) continue;
    SwarmUav& u = uavs[j];
    if (!u.arrived_s && horizontal(u.pos, out.target) <= s.converge_radius_m) u.arrived_s = t - *out.detect_s;
    all = all && u.arrived_s.has_value();
  }
  if (all) {
    out.converge_s = t - *out.detect_s;
    return true;
  }
  return t - *out.detect_s >= s.converge_limit_s;
}

}  // namespace

ShostakSwarmRun shostak_swarm_run(const ShostakSwarmSetup& s, uint64_t seed) {
  const SwarmConstants k(s);
  ShostakSwarmRun out;
  draw_target_and_obstacles(out, s, k, seed);

  ShostakLayers layers(Rect{0, 0, s.cells, s.cells}, k.lp);  // the shared /swarm/pheromone_map
  const ShostakLookup lookup = [&](Cell c) { return layers.values(c); };
  SeenCells seen(s.cells);
  std::vector<SwarmUav> uavs = launch_uavs(s, k, seed);
  SwarmState w{layers, lookup, seen, uavs};

  const auto limit_ticks = static_cast<int>(std::lround((s.search_limit_s + s.converge_limit_s) / k.dt));
  for (int tick = 1; tick <= limit_ticks; ++tick) {
    const double t = tick * k.dt;
    out.end_s = t;
    for (uint32_t i = 0; i < s.uavs; ++i) swarm_uav_tick(out, w, i, tick, t, s, k);
    if (tick % 5 == 0) out.coverage.emplace_back(t, seen.share());
    layers.evaporate(k.dt);  // Shostak 2024 eq. (2)
    if (swarm_run_over(out, uavs, t, s)) break;
  }
  for (uint32_t j = 0; j < s.uavs; ++j) {
    if (out.detect_s && j != out.detector) out.arrival_s.push_back(uavs[j].arrived_s.value_or(std::nan("")));
    out.tracks.push_back(std::move(uavs[j].track));
  }
  return out;
}

}  // namespace pheromesh::core
