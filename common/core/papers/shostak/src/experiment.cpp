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

}  // namespace

ShostakSwarmRun shostak_swarm_run(const ShostakSwarmSetup& s, uint64_t seed) {
  const ShostakLayerParams lp;  // 5 m cells, +1 per 0.2 s, ρ = 0.05, τmax 10 / 10 / 100
  const ShostakAcoParams aco;   // N = 20, d = 15 m, ψ ∈ ±30°, α = 1.5, β = 3
  const ShostakAttractivenessParams attr;
  const double size_m = s.cells * lp.cell_size_m;
  const double dt = lp.deposit_period_s;
  const Vec3 launch(0.5 * size_m, 0.5 * size_m, s.altitude_m);

  ShostakSwarmRun out;
  Rng world(stream_seed(seed, "scenario", 0));
  auto uniform_xy = [&](double margin) {
    return Vec3(margin + (size_m - 2 * margin) * world.uniform01(), margin + (size_m - 2 * margin) * world.uniform01(),
                0.0);
  };
  do {
    out.target = uniform_xy(lp.cell_size_m);
  } while (horizontal(out.target, launch) < s.target_min_distance_m);
  for (uint32_t k = 0; k < s.obstacles; ++k) out.obstacles.push_back(uniform_xy(lp.cell_size_m));

  const Rect map{0, 0, s.cells, s.cells};
  ShostakLayers layers(map, lp);  // the shared /swarm/pheromone_map
  const ShostakLookup lookup = [&](Cell c) { return layers.values(c); };
  std::vector<char> visited(static_cast<std::size_t>(s.cells) * static_cast<std::size_t>(s.cells), 0);
  std::size_t visited_count = 0;
  std::vector<SwarmUav> uavs(s.uavs);
  for (uint32_t i = 0; i < s.uavs; ++i) {
    uavs[i].pos = launch;
    uavs[i].heading = shostak_dispersal_heading(i, s.uavs);  // Shostak 2024 Sec. 5: 0°/120°/240°
    uavs[i].waypoint = shostak_dispersal_waypoint(launch, i, s.uavs, s.dispersal_m);
    uavs[i].rng = Rng(stream_seed(seed, "uav", i));
  }

  const double step_m = s.speed_mps * dt;
  const auto limit_ticks = static_cast<int>(std::lround((s.search_limit_s + s.converge_limit_s) / dt));
  for (int tick = 1; tick <= limit_ticks; ++tick) {
    const double t = tick * dt;
    out.end_s = t;
    for (uint32_t i = 0; i < s.uavs; ++i) {
      SwarmUav& u = uavs[i];
      if (!u.waypoint) {
        // Shostak 2024 Sec. 3.4, Shostak 2024 Sec. 3.5: the next waypoint by roulette; η prefers the
        // reported target's bearing after the broadcast, the current heading before.
        std::optional<double> preferred = u.heading;
        if (out.detect_s) preferred = std::atan2(out.target.y() - u.pos.y(), out.target.x() - u.pos.x());
        const auto choice = shostak_choose(u.pos, preferred, lookup, lp.cell_size_m, aco, attr, u.rng);
        if (choice) {
          Vec3 w = choice->candidate.position;
          w.z() = std::clamp(w.z(), s.min_altitude_m, s.max_altitude_m);
          u.waypoint = w;
        } else {  // every candidate off the map: head back toward the middle
          const Vec3 back = launch - u.pos;
          u.waypoint = u.pos + aco.step_m * back.normalized();
        }
      }
      const Vec3 to = *u.waypoint - u.pos;
      if (to.norm() <= step_m) {
        u.pos = *u.waypoint;
        u.waypoint.reset();
      } else {
        u.pos += step_m * to.normalized();
      }
      if (to.head<2>().norm() > 1e-9) u.heading = std::atan2(to.y(), to.x());
      const Cell here = shostak_cell_of(u.pos, lp.cell_size_m);
      layers.deposit_explored(here);  // Shostak 2024 eq. (1), every 0.2 s
      if (map.contains(here)) {
        char& seen = visited[static_cast<std::size_t>(here.y) * static_cast<std::size_t>(s.cells) +
                             static_cast<std::size_t>(here.x)];
        if (seen == 0) ++visited_count;
        seen = 1;
      }
      for (const Vec3& o : out.obstacles) {
        if (horizontal(o, u.pos) <= s.lidar_range_m) layers.mark_hazard(here);  // Shostak 2024 Sec. 4.2
      }
      if (!out.detect_s && horizontal(out.target, u.pos) <= s.detect_radius_m) {
        // Shostak 2024 Sec. 5: target pheromone 100 at the target and an immediate broadcast.
        out.detect_s = t;
        out.detector = i;
        layers.mark_target(shostak_cell_of(out.target, lp.cell_size_m));
        double farthest = 0.0;
        for (uint32_t j = 0; j < s.uavs; ++j) {
          if (j == i) continue;
          uavs[j].waypoint.reset();  // the others turn toward the target at once
          farthest = std::max(farthest, horizontal(uavs[j].pos, out.target));
        }
        out.direct_s = std::max(0.0, farthest - s.converge_radius_m) / s.speed_mps;
      }
      if (tick % 5 == 0) u.track.emplace_back(u.pos.x(), u.pos.y());
    }
    if (tick % 5 == 0) {
      out.coverage.emplace_back(t, static_cast<double>(visited_count) / static_cast<double>(visited.size()));
    }
    layers.evaporate(dt);  // Shostak 2024 eq. (2)

    if (!out.detect_s) {
      if (t >= s.search_limit_s) break;
      continue;
    }
    bool all = true;
    for (uint32_t j = 0; j < s.uavs; ++j) {
      if (j == out.detector) continue;
      SwarmUav& u = uavs[j];
      if (!u.arrived_s && horizontal(u.pos, out.target) <= s.converge_radius_m) u.arrived_s = t - *out.detect_s;
      all = all && u.arrived_s.has_value();
    }
    if (all) {
      out.converge_s = t - *out.detect_s;
      break;
    }
    if (t - *out.detect_s >= s.converge_limit_s) break;
  }
  for (uint32_t j = 0; j < s.uavs; ++j) {
    if (out.detect_s && j != out.detector) out.arrival_s.push_back(uavs[j].arrived_s.value_or(std::nan("")));
    out.tracks.push_back(std::move(uavs[j].track));
  }
  return out;
}

}  // namespace pheromesh::core
