// Shostak 2024 Sec. 5 experiments as a library: the evaporation of the
// explored layer (Shostak 2024 eq. (2), "10 -> 5 in about 14 s"), a drone hovering over one
// cell (Shostak 2024 eq. (1)), and the swarm loop behind `pheromesh experiment
// shostak-convergence`, built on the core's layers, candidates (Shostak 2024 eq. (4)),
// scoring (Shostak 2024 eq. (3), Shostak 2024 eq. (5)) and roulette (Shostak 2024 eq. (6)). The CLI only formats.
//
// The swarm loop (ours where Shostak 2024 Sec. 5 is silent, see ShostakSwarmSetup):
//  * One shared map of three layers (the /swarm/pheromone_map topic, ideal
//    pose as in the paper's Gazebo runs, Shostak 2024 Sec. 4.1), evaporated every 0.2 s by
//    (1-ρ)^0.2.
//  * Per 0.2 s tick, UAVs in index order: a UAV without a waypoint draws one
//    by shostak_choose (η prefers its heading while searching, the bearing to
//    the target after the broadcast); if every candidate is off the map it
//    heads back toward the launch point. It moves step = speed·0.2 s toward
//    the waypoint, deposits explored (Shostak 2024 eq. (1)) in its cell, marks hazard if a
//    point obstacle is within lidar range (Shostak 2024 Sec. 4.2), and detects the target within
//    detect_radius_m: target pheromone 100 and an immediate broadcast (Shostak 2024 Sec. 5), on
//    which every other UAV drops its waypoint.
//  * Random numbers: the target, then the obstacles, from
//    stream_seed(seed, "scenario", 0) (two uniform draws per point, target
//    redrawn until far enough from launch); UAV i from stream_seed(seed, "uav", i).
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "pheromesh/shostak/model.hpp"

namespace pheromesh::core {

// First multiple of dt_s at which one cell that starts at `from` in the
// explored layer is at or below `to`, evaporating by Shostak 2024 eq. (2) in steps
// of dt_s [s]. NaN if not reached within 100000 steps.
double shostak_explored_crossing_s(const ShostakLayerParams& params, double from, double to, double dt_s);

// A drone over one cell: +1 explored every deposit period while t <= hover_s
// (Shostak 2024 eq. (1)), evaporation before each deposit (Shostak 2024 eq. (2)).
struct ShostakHoverTrace {
  std::vector<std::pair<double, double>> points;  // (t [s], explored), from (0, 0), one per period
  std::optional<double> full_s;                   // first t at which explored reached explored_max
};
ShostakHoverTrace shostak_hover(const ShostakLayerParams& params, double hover_s, uint32_t periods);

// Values the paper leaves open (ours), and the paper's own.
struct ShostakSwarmSetup {
  uint32_t uavs = 3;                    // Shostak 2024 Sec. 5: three drones
  int32_t cells = 40;                   // Shostak 2024 Sec. 2: 40 x 40 cells of 5 m
  double speed_mps = 5.0;               // ours: cruise speed (not given) [m/s]
  double altitude_m = 10.0;             // ours: take-off altitude [m]
  double min_altitude_m = 5.0;          // ours: candidates' z kept in [5, 30] m
  double max_altitude_m = 30.0;
  double dispersal_m = 50.0;            // ours: length of the 0°/120°/240° dispersal leg [m]
  double detect_radius_m = 10.0;        // ours: camera footprint radius (horizontal) [m]
  double lidar_range_m = 10.0;          // ours: "obstacle at the set distance" (Shostak 2024 Sec. 4.2) [m]
  uint32_t obstacles = 4;               // ours: point obstacles that feed the hazard layer
  double target_min_distance_m = 40.0;  // ours: target at least this far from the launch point [m]
  double converge_radius_m = 15.0;      // ours: "arrived" = within one step d of the target [m]
  double search_limit_s = 600.0;        // ours: give up searching [s]
  double converge_limit_s = 300.0;      // ours: give up converging [s]
};

struct ShostakSwarmRun {
  std::optional<double> detect_s;    // first detection (= broadcast) [s]
  uint32_t detector = 0;             // index of the detecting UAV
  std::optional<double> converge_s;  // broadcast -> all others within converge_radius_m [s]
  std::vector<double> arrival_s;     // per other UAV (index order), after the broadcast; NaN: never
  double direct_s = 0.0;             // farthest other UAV's straight-line time at the broadcast [s]
  // Per UAV, its (x, y) [m] every 5 ticks (1 s).
  std::vector<std::vector<std::pair<double, double>>> tracks;
  // (t [s], share of the map's cells a UAV has been in) every 5 ticks (1 s).
  std::vector<std::pair<double, double>> coverage;
  double end_s = 0.0;  // time of the last tick
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> obstacles;
};

// One seeded run of the swarm (see the top of this file).
ShostakSwarmRun shostak_swarm_run(const ShostakSwarmSetup& setup, uint64_t seed);

}  // namespace pheromesh::core
