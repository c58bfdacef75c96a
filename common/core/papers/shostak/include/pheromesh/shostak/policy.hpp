// Scenario parameters of the Shostak GPS-denied stigmergy policy
// (shostak/src/policy.cpp; scenario.policy.shostak, docs/policies/shostak.md).
//
// The paper's constants keep their names from pheromesh/shostak/model.hpp (layers, Shostak 2024 eq. (1), Shostak 2024 eq. (2), Shostak 2024 eq. (3), Shostak 2024 eq. (4), Shostak 2024 eq. (5), Shostak 2024 eq. (6)
// parameters, drift model); the rest are our choices for what the paper leaves
// open, the same as the in-experiment swarm loop (experiments/shostak.cpp,
// SwarmSetup).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/policy_table.hpp"
#include "pheromesh/shostak/model.hpp"

namespace pheromesh::core {

struct ShostakConfig final : PolicyConfig {
  static constexpr std::string_view kPolicy = "shostak";
  [[nodiscard]] std::string_view policy() const override { return kPolicy; }

  // One tick is one deposit period of Shostak 2024 Sec. 3.1 (0.2 s): one explored deposit, one
  // motion step of speed·dt, one Shostak 2024 eq. (2) evaporation by (1-ρ)^dt. Other values
  // keep the physics (deposits at multiples of the deposit period, speed in
  // m/s, ρ per second).
  double dt_s = 0.2;  // [s] (0, 1]

  ShostakLayerParams layers;                    // Shostak 2024 eq. (1), Shostak 2024 eq. (2), Shostak 2024 Sec. 2, Shostak 2024 Sec. 4.2, Shostak 2024 Sec. 5; cell_size_m [m/cell]
  ShostakAcoParams aco;                         // Shostak 2024 eq. (4), Shostak 2024 eq. (5), Shostak 2024 eq. (6): N, d, ψmax, α, β, our η floor
  ShostakAttractivenessParams attractiveness;   // Shostak 2024 eq. (3) (not configurable)
  ShostakDriftParams drift;                     // ours: dead-reckoning drift, 0 = ideal pose (Shostak 2024 Sec. 4.1)

  // Ours (the paper gives none of these; values of SwarmSetup in
  // experiments/shostak.cpp).
  double speed_mps = 5.0;         // [m/s] cruise speed
  double altitude_m = 10.0;       // [m] take-off (and dispersal) altitude above the take-off point
  double min_altitude_m = 5.0;    // [m] waypoints' z clamped into [min, max]
  double max_altitude_m = 30.0;   // [m]
  double dispersal_m = 50.0;      // [m] length of the 2π·i/n dispersal leg (Shostak 2024 Sec. 5), shortened to stay on the map
  double detect_radius_m = 10.0;  // [m] horizontal camera footprint radius: a target closer is detected
  double lidar_range_m = 10.0;    // [m] "obstacle at the set distance" of Shostak 2024 Sec. 4.2 (horizontal)
  // Yaw of UAV i's local frame in the map frame [rad], fixed at take-off
  // (Shostak 2024 Sec. 4.1); UAVs beyond the list use 0.
  std::vector<double> frame_yaw_rad;

  // How a UAV flies to a reported target. Roulette: the paper, Shostak 2024 eq. (4) to Shostak 2024 eq. (6)
  // with η preferring the bearing to the target (Shostak 2024 Sec. 5). Beeline: ours, the
  // shostak_beeline variant (docs/policies/shostak.md): once a target is known,
  // each waypoint is a step of d straight toward the nearest one; the search
  // before any report is the paper's.
  enum class Converge : uint8_t { Roulette = 0, Beeline = 1 };
  Converge converge = Converge::Roulette;
};

// The beeline waypoint (ours): from `from` toward `target` (local frame, the
// target's z ignored), a horizontal step of min(step_m, distance) at the
// altitude of `from`; nullopt when already over the target (within 1e-6 m).
std::optional<Eigen::Vector3d> shostak_beeline_waypoint(const Eigen::Vector3d& from, const Eigen::Vector3d& target,
                                                        double step_m);

// --- the policy (policy.cpp), reached through the room's entry of the policy
// table, kShostakPolicy (defined in src/scenario.cpp)
extern const PolicyEntry kShostakPolicy;
PolicyTraits shostak_traits(const ScenarioConfig& s);
std::unique_ptr<UavPolicy> make_shostak_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& world, uint32_t id);
std::unique_ptr<PlaceModel> make_shostak_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region);
std::map<std::string, double> shostak_field_summary(const ScenarioConfig& s, const FieldLookup& value);

}  // namespace pheromesh::core
