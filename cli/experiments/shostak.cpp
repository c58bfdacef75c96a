// Shostak 2024 Sec. 5: evaporation of the explored layer (Shostak 2024 eq. (2), "10 -> 5
// in about 14 s") and the swarm's convergence on a detected target, with a
// small in-file swarm loop built on the core's layers, candidates (Shostak 2024 eq. (4)),
// scoring (Shostak 2024 eq. (3), Shostak 2024 eq. (5)) and roulette (Shostak 2024 eq. (6)).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

#include "experiment.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/shostak/model.hpp"

namespace pheromesh::cli::experiments {

namespace {

using core::ShostakLayer;
using core::ShostakLayers;
using Vec3 = Eigen::Vector3d;

std::string fmt(double v, int prec = 2) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

// ---------------------------------------------------------------- evaporation

// First multiple of dt_s at which a cell that starts at `from` is at or below
// `to`, evaporating by Shostak 2024 eq. (2) in steps of dt_s seconds.
double layer_crossing(double from, double to, double dt_s) {
  ShostakLayers layers({0, 0, 1, 1}, core::ShostakLayerParams{});
  layers.deposit(ShostakLayer::Explored, {0, 0}, from);
  for (int k = 1; k < 100000; ++k) {
    layers.evaporate(dt_s);
    if (layers.value(ShostakLayer::Explored, {0, 0}) <= to) return k * dt_s;
  }
  return std::nan("");
}

Report run_evaporation(uint32_t /*runs*/, const Progress& progress) {
  const core::ShostakLayerParams lp;
  Report rep;
  rep.title = "Shostak §5 — explored layer 10 → 5 under eq. (2)";
  rep.source = "Shostak & Petrenko, §3.1–3.2 (eqs. (1)–(2)) and §5";
  rep.setup = "one cell of ShostakLayers: explored = 10, ρ = 0.05 per second (τ ← τ·(1−ρ)^dt), deposits of +1 every "
              "0.2 s capped at 10; deterministic, 1 run";

  const double whole_seconds = layer_crossing(10.0, 5.0, 1.0);
  const double ticks = layer_crossing(10.0, 5.0, lp.deposit_period_s);
  const double half_life = core::shostak_half_life_s(lp.evaporation_rate);
  const double exp_reading = std::log(2.0) / lp.evaporation_rate;

  // Hovering over one cell: +1 every 0.2 s with evaporation in between; when the cap is reached.
  ShostakLayers hover({0, 0, 1, 1}, lp);
  Series fill{"hover 5 s, then leave", {{0.0, 0.0}}};
  double t_full = std::nan("");
  const double dt = lp.deposit_period_s;
  for (int k = 1; k <= 300; ++k) {
    const double t = k * dt;
    hover.evaporate(dt);
    if (t <= 5.0 + 1e-9) hover.deposit_explored({0, 0});
    const double v = hover.value(ShostakLayer::Explored, {0, 0});
    if (std::isnan(t_full) && v >= lp.explored_max - 1e-6) t_full = t;
    fill.points.emplace_back(t, v);
  }

  rep.rows = {
      {"explored 10 → ≤ 5, eq. (2) in whole-second steps", 14.0, {whole_seconds}, "s",
       "10·0.95¹³ = 5.13, 10·0.95¹⁴ = 4.88"},
      {"explored 10 → ≤ 5, eq. (2) in 0.2 s map ticks", 14.0, {ticks}, "s", "(1−ρ)^0.2 per tick"},
      {"half-life ln 0.5 / ln(1−ρ)", 14.0, {half_life}, "s", "continuous form of eq. (2)"},
      {"half-life if ρ were a continuous rate, ln 2 / ρ", 14.0, {exp_reading}, "s",
       "a reading the paper does not use; shown because it also rounds to 14"},
      {"hovering: time until explored reaches the cap 10", std::nullopt, {t_full}, "s",
       "§5: \"accumulate to 10.00 (max) over some time\"; no number given"},
  };

  Plot p{"explored.svg", "Explored layer after one visit: 10 → 5 (§5)", "t [s]", "explored τ_e", {}};
  Series sec{"eq. (2), 1 s steps", {}}, tick{"eq. (2), 0.2 s ticks", {}}, cont{"e^(−ρt) (not the paper's)", {}};
  ShostakLayers a({0, 0, 1, 1}, lp), b({0, 0, 1, 1}, lp);
  a.deposit(ShostakLayer::Explored, {0, 0}, 10.0);
  b.deposit(ShostakLayer::Explored, {0, 0}, 10.0);
  rep.csv_header = {"t_s", "explored_1s_steps", "explored_0.2s_ticks", "exp_minus_rho_t"};
  for (int k = 0; k <= 300; ++k) {
    const double t = k * dt;
    if (k > 0) b.evaporate(dt);
    if (k > 0 && k % 5 == 0) a.evaporate(1.0);
    if (k % 5 == 0) sec.points.emplace_back(t, a.value(ShostakLayer::Explored, {0, 0}));
    tick.points.emplace_back(t, b.value(ShostakLayer::Explored, {0, 0}));
    cont.points.emplace_back(t, 10.0 * std::exp(-lp.evaporation_rate * t));
    if (k % 5 == 0) {
      rep.csv_rows.push_back({fmt(t, 1), fmt(a.value(ShostakLayer::Explored, {0, 0}), 4),
                              fmt(b.value(ShostakLayer::Explored, {0, 0}), 4), fmt(cont.points.back().second, 4)});
    }
  }
  p.series = {sec, tick, cont, {"5.0", {{0.0, 5.0}, {60.0, 5.0}}}};
  rep.plots.push_back(p);
  Plot q{"hover.svg", "Explored under a hovering drone, then evaporating", "t [s]", "explored τ_e", {}};
  q.series = {fill, {"cap 10", {{0.0, 10.0}, {60.0, 10.0}}}};
  rep.plots.push_back(q);

  rep.notes = {
      "Eq. (2) multiplies by (1−ρ) once per second of discrete time, so 10 first drops below 5 at t = 14 s, as §5 "
      "says (10·0.95¹⁴ = 4.88). The exact half-life is 13.51 s. Our map evaporates every 0.2 s by (1−ρ)^0.2, which "
      "is the same law: five ticks equal one second. It first reads at or below 5 at t = 13.6 s.",
      "A hovering drone adds +1 every 0.2 s (eq. (1)). With evaporation in between, the cell reaches the cap of 10 "
      "after 11 deposits, at t = 2.2 s (last row). The paper gives no time for this.",
  };
  progress(1, 1);
  return rep;
}

// ------------------------------------------------------------------ the swarm

// Values the paper leaves open (ours), and the paper's own.
struct SwarmSetup {
  uint32_t uavs = 3;                 // Shostak 2024 Sec. 5: three drones
  int32_t cells = 40;                // Shostak 2024 Sec. 2: 40 x 40 cells of 5 m
  double speed_mps = 5.0;            // ours: cruise speed (not given)
  double altitude_m = 10.0;          // ours: take-off altitude
  double min_altitude_m = 5.0;       // ours: candidates' z kept in [5, 30] m
  double max_altitude_m = 30.0;
  double dispersal_m = 50.0;         // ours: length of the 0°/120°/240° dispersal leg
  double detect_radius_m = 10.0;     // ours: camera footprint radius (horizontal)
  double lidar_range_m = 10.0;       // ours: "obstacle at the set distance" (Shostak 2024 Sec. 4.2)
  uint32_t obstacles = 4;            // ours: point obstacles that feed the hazard layer
  double target_min_distance_m = 40.0;  // ours: target at least this far from the launch point
  double converge_radius_m = 15.0;   // ours: "arrived" = within one step d of the target
  double search_limit_s = 600.0;     // ours: give up searching
  double converge_limit_s = 300.0;   // ours: give up converging
};

struct Uav {
  Vec3 pos = Vec3::Zero();
  std::optional<Vec3> waypoint;
  bool dispersed = false;
  double heading = 0.0;  // azimuth of the last move [rad]
  core::Rng rng{0};
  std::optional<double> arrived_s;  // after the broadcast
  Series track;
};

struct SwarmRun {
  std::optional<double> detect_s;    // first detection (= broadcast)
  uint32_t detector = 0;
  std::optional<double> converge_s;  // broadcast -> all others within the radius
  std::vector<double> arrival_s;     // per other UAV, after the broadcast (NaN: never)
  double direct_s = 0.0;             // farthest other UAV's straight-line time at the broadcast
  std::vector<Series> tracks;        // x/y [m]
  Vec3 target = Vec3::Zero();
  std::vector<Vec3> obstacles;
};

double horizontal(const Vec3& a, const Vec3& b) { return std::hypot(a.x() - b.x(), a.y() - b.y()); }

SwarmRun run_swarm(const SwarmSetup& s, uint64_t seed) {
  const core::ShostakLayerParams lp;  // 5 m cells, +1 per 0.2 s, ρ = 0.05, τmax 10 / 10 / 100
  const core::ShostakAcoParams aco;   // N = 20, d = 15 m, ψ ∈ ±30°, α = 1.5, β = 3
  const core::ShostakAttractivenessParams attr;
  const double size_m = s.cells * lp.cell_size_m;
  const double dt = lp.deposit_period_s;
  const Vec3 launch(0.5 * size_m, 0.5 * size_m, s.altitude_m);

  SwarmRun out;
  core::Rng world(core::stream_seed(seed, "scenario", 0));
  auto uniform_xy = [&](double margin) {
    return Vec3(margin + (size_m - 2 * margin) * world.uniform01(), margin + (size_m - 2 * margin) * world.uniform01(),
                0.0);
  };
  do {
    out.target = uniform_xy(lp.cell_size_m);
  } while (horizontal(out.target, launch) < s.target_min_distance_m);
  for (uint32_t k = 0; k < s.obstacles; ++k) out.obstacles.push_back(uniform_xy(lp.cell_size_m));

  ShostakLayers layers({0, 0, s.cells, s.cells}, lp);  // the shared /swarm/pheromone_map
  const core::ShostakLookup lookup = [&](core::Cell c) { return layers.values(c); };
  std::vector<Uav> uavs(s.uavs);
  for (uint32_t i = 0; i < s.uavs; ++i) {
    uavs[i].pos = launch;
    uavs[i].heading = core::shostak_dispersal_heading(i, s.uavs);
    uavs[i].waypoint = core::shostak_dispersal_waypoint(launch, i, s.uavs, s.dispersal_m);
    uavs[i].rng = core::Rng(core::stream_seed(seed, "uav", i));
    uavs[i].track.name = "UAV " + std::to_string(i + 1);
  }

  const double step_m = s.speed_mps * dt;
  const auto limit_ticks = static_cast<int>(std::lround((s.search_limit_s + s.converge_limit_s) / dt));
  for (int tick = 1; tick <= limit_ticks; ++tick) {
    const double t = tick * dt;
    for (uint32_t i = 0; i < s.uavs; ++i) {
      Uav& u = uavs[i];
      if (!u.waypoint) {
        // Shostak 2024 Sec. 3.4, Shostak 2024 Sec. 3.5: the next waypoint by roulette; η prefers the reported
        // target's bearing after the broadcast, the current heading before.
        std::optional<double> preferred = u.heading;
        if (out.detect_s) preferred = std::atan2(out.target.y() - u.pos.y(), out.target.x() - u.pos.x());
        const auto choice = core::shostak_choose(u.pos, preferred, lookup, lp.cell_size_m, aco, attr, u.rng);
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
      const core::Cell here = core::shostak_cell_of(u.pos, lp.cell_size_m);
      layers.deposit_explored(here);  // Shostak 2024 eq. (1), every 0.2 s
      for (const Vec3& o : out.obstacles) {
        if (horizontal(o, u.pos) <= s.lidar_range_m) layers.mark_hazard(here);  // Shostak 2024 Sec. 4.2
      }
      if (!out.detect_s && horizontal(out.target, u.pos) <= s.detect_radius_m) {
        // Shostak 2024 Sec. 5: target pheromone 100 at the target and an immediate broadcast.
        out.detect_s = t;
        out.detector = i;
        layers.mark_target(core::shostak_cell_of(out.target, lp.cell_size_m));
        double farthest = 0.0;
        for (uint32_t j = 0; j < s.uavs; ++j) {
          if (j == i) continue;
          uavs[j].waypoint.reset();  // the others turn toward the target at once
          farthest = std::max(farthest, horizontal(uavs[j].pos, out.target));
        }
        out.direct_s = std::max(0.0, farthest - s.converge_radius_m) / s.speed_mps;
      }
      if (tick % 5 == 0) u.track.points.emplace_back(u.pos.x(), u.pos.y());
    }
    layers.evaporate(dt);  // Shostak 2024 eq. (2)

    if (!out.detect_s) {
      if (t >= s.search_limit_s) break;
      continue;
    }
    bool all = true;
    for (uint32_t j = 0; j < s.uavs; ++j) {
      if (j == out.detector) continue;
      Uav& u = uavs[j];
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

Series circle(const std::string& name, const Vec3& c, double r) {
  Series s{name, {}};
  for (int k = 0; k <= 48; ++k) {
    const double a = 2.0 * std::numbers::pi * k / 48.0;
    s.points.emplace_back(c.x() + r * std::cos(a), c.y() + r * std::sin(a));
  }
  return s;
}

Report run_convergence(uint32_t runs, const Progress& progress) {
  const SwarmSetup s;
  Report rep;
  rep.title = "Shostak §5 — swarm convergence after a target is detected";
  rep.source = "Shostak & Petrenko, §2–§5 (eqs. (1)–(6)), Fig. 3";
  rep.setup = std::to_string(s.uavs) + " UAVs from the centre of the 40 x 40 map of 5 m cells, dispersal legs of " +
              fmt(s.dispersal_m, 0) + " m at 0°/120°/240°, then eq. (4)–(6) waypoints (N = 20, d = 15 m, α = 1.5, "
              "β = 3) at " + fmt(s.speed_mps, 0) + " m/s; shared explored/hazard/target layers, +1 explored every "
              "0.2 s, ρ = 0.05/s; one random target (≥ " + fmt(s.target_min_distance_m, 0) + " m from launch, "
              "detected within " + fmt(s.detect_radius_m, 0) + " m) and " + std::to_string(s.obstacles) +
              " point obstacles per seed; " + std::to_string(runs) + " runs, seeds 1.." + std::to_string(runs);

  std::vector<double> detect, converge, each, direct, ratio;
  uint32_t never_detected = 0, never_converged = 0;
  std::optional<SwarmRun> shown;
  rep.csv_header = {"run", "seed", "detect_s", "detector", "converge_s", "arrivals_s", "direct_s"};
  for (uint32_t run = 0; run < runs; ++run) {
    const uint64_t seed = run + 1;
    SwarmRun r = run_swarm(s, seed);
    std::string arrivals;
    for (double a : r.arrival_s) {
      arrivals += (arrivals.empty() ? "" : " ") + (std::isnan(a) ? std::string("never") : fmt(a, 1));
      if (!std::isnan(a)) each.push_back(a);
    }
    if (!r.detect_s) {
      ++never_detected;
    } else {
      detect.push_back(*r.detect_s);
      direct.push_back(r.direct_s);
      if (r.converge_s) {
        converge.push_back(*r.converge_s);
        if (r.direct_s > 0.0) ratio.push_back(*r.converge_s / r.direct_s);
      } else {
        ++never_converged;
      }
    }
    rep.csv_rows.push_back({std::to_string(run), std::to_string(seed), r.detect_s ? fmt(*r.detect_s, 1) : "",
                            r.detect_s ? std::to_string(r.detector + 1) : "",
                            r.converge_s ? fmt(*r.converge_s, 1) : "", arrivals, r.detect_s ? fmt(r.direct_s, 1) : ""});
    if (!shown && r.converge_s) shown = std::move(r);
    progress(run + 1, runs);
  }

  const std::string radius = fmt(s.converge_radius_m, 0) + " m";
  rep.rows = {
      {"time to the first detection (broadcast)", std::nullopt, detect, "s",
       std::to_string(never_detected) + " run(s) found nothing within " + fmt(s.search_limit_s, 0) + " s"},
      {"broadcast → all other UAVs within " + radius + " of the target", std::nullopt, converge, "s",
       "§5 gives no number (\"rapid convergence of all drones\"); " + std::to_string(never_converged) +
           " run(s) did not converge within " + fmt(s.converge_limit_s, 0) + " s"},
      {"broadcast → one other UAV within " + radius, std::nullopt, each, "s", "every other UAV of every run pooled"},
      {"straight-line time for the farthest other UAV", std::nullopt, direct, "s",
       "(distance − " + radius + ") / " + fmt(s.speed_mps, 0) + " m/s: the lower bound"},
      {"convergence time / straight-line time", std::nullopt, ratio, "ratio",
       "cost of choosing among 20 random candidates instead of flying straight"},
  };

  if (shown) {
    Plot p{"convergence.svg", "Tracks of the first converged run (cf. Fig. 3)", "x [m]", "y [m]", {}};
    p.series = shown->tracks;
    p.series.push_back(circle("target (" + radius + ")", shown->target, s.converge_radius_m));
    for (std::size_t k = 0; k < shown->obstacles.size(); ++k) {
      p.series.push_back(circle("obstacle " + std::to_string(k + 1), shown->obstacles[k], 2.0));
    }
    p.series.push_back({"map edge", {{0.0, 0.0}, {200.0, 0.0}, {200.0, 200.0}, {0.0, 200.0}, {0.0, 0.0}}});
    rep.plots.push_back(p);
  }

  rep.notes = {
      "§5 says only: «При виявленні цілі спостерігається швидка конвергенція всіх дронів. … Інші дрони миттєво "
      "отримують координати та починають політ до цілі» (\"When a target is detected, all drones rapidly converge. "
      "… The other drones receive its coordinates immediately and start flying to the target\", Fig. 3). It gives no "
      "time, radius or run count, so no row here has a paper value.",
      "From the paper we keep 3 drones, the 40 x 40 map of 5 m cells, the 0°/120°/240° dispersal, and eqs. (1)–(6) "
      "with their constants (+1 explored every 0.2 s, +5 hazard, +100 target, ρ = 0.05/s, N = 20, d = 15 m, "
      "ψ ∈ ±30°, α = 1.5, β = 3). The paper does not give the rest, so these are ours: 5 m/s cruise speed, 50 m "
      "dispersal legs from the map centre, altitude kept in 5–30 m, 10 m detection radius, 4 random point "
      "obstacles that add hazard within 10 m and do not block flight, and a 15 m arrival radius (one step d).",
      "The heuristic η of eq. (5) is undefined in the paper. We use the core's η: alignment with the current "
      "heading while searching, and with the bearing to the broadcast target afterwards (floor 0.1, cubed by β). "
      "After the broadcast, each other drone drops its waypoint and draws a new one at once. The roulette still "
      "picks among 20 random directions, so a drone zig-zags toward the target rather than flying straight. The "
      "ratio row measures the cost of that.",
      "All drones share one pheromone map (the /swarm/pheromone_map topic, with ideal pose as in the paper's Gazebo "
      "runs, §4.1). Layers evaporate every 0.2 s by (1−ρ)^0.2. The swarm loop lives in this file, seeded per run "
      "and per UAV (stream_seed), so every run can be repeated exactly.",
  };
  return rep;
}

}  // namespace

std::vector<Experiment> shostak_experiments() {
  return {
      {"shostak-evaporation", "Shostak §5: explored 10 → 5 in ≈14 s under eq. (2)", 1,
       [](uint32_t runs, const Progress& p) { return run_evaporation(runs, p); }},
      {"shostak-convergence",
       "Shostak §5 / Fig. 3: 3-drone swarm, time from a target broadcast until the others reach it", 10,
       [](uint32_t runs, const Progress& p) { return run_convergence(runs, p); }},
  };
}

}  // namespace pheromesh::cli::experiments
