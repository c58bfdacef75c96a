// Liu 2022 Sec. 5 simulation: the time loop of Liu 2022 Algorithm 1 around the pure pieces
// of liu/src/tpm.cpp. The choices the paper leaves open are listed in
// pheromesh/liu/swarm.hpp and pheromesh/liu/tpm.hpp; this file only wires them together.
#include "pheromesh/liu/swarm.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <utility>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/rng.hpp"

namespace pheromesh::core {

namespace {

std::size_t cell_index(Cell c, int32_t w) {
  return static_cast<std::size_t>(c.y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(c.x);
}

bool inside_map(Vec2 p, const LiuParams& params) {
  return std::isfinite(p.x) && std::isfinite(p.y) && p.x >= 0.0 && p.y >= 0.0 &&
         p.x <= params.grid_width * params.cell_size_m && p.y <= params.grid_height * params.cell_size_m;
}

std::optional<Error> check_config(const LiuSwarmConfig& c) {
  const LiuParams& p = c.params;
  if (p.grid_width <= 0 || p.grid_height <= 0) return Error{"liu swarm: grid_width and grid_height must be > 0"};
  if (!(p.cell_size_m > 0.0)) return Error{"liu swarm: cell_size_m must be > 0"};
  if (p.uav_count == 0) return Error{"liu swarm: uav_count must be > 0"};
  if (!(p.dt_s > 0.0) || !(p.cycle_s >= p.dt_s)) return Error{"liu swarm: need 0 < dt_s <= cycle_s"};
  if (!(p.p_detection >= 0.0 && p.p_detection <= 1.0)) return Error{"liu swarm: p_detection must be in [0, 1]"};
  // Liu 2022 eq. (5) divides by 1 - Pf.
  if (!(p.p_false_alarm >= 0.0 && p.p_false_alarm < 1.0)) return Error{"liu swarm: p_false_alarm must be in [0, 1)"};
  if (!std::isfinite(p.confirm_threshold)) return Error{"liu swarm: confirm_threshold must be finite"};
  if (!(p.initial_probability >= 0.0 && p.initial_probability <= 1.0)) {
    return Error{"liu swarm: initial_probability must be in [0, 1]"};
  }
  if (c.policy == LiuPolicy::kLawnmower) {
    if (static_cast<int64_t>(p.uav_count) > p.grid_height) {
      return Error{"liu swarm: the mower needs at most one UAV per grid row (" + std::to_string(p.uav_count) +
                   " UAVs, " + std::to_string(p.grid_height) + " rows)"};
    }
  } else {
    if (c.starts.size() < p.uav_count) {
      return Error{"liu swarm: " + std::to_string(c.starts.size()) + " start positions for " +
                   std::to_string(p.uav_count) + " UAVs"};
    }
    for (std::size_t i = 0; i < p.uav_count; ++i) {
      if (!inside_map(c.starts[i], p)) return Error{"liu swarm: start position " + std::to_string(i) + " is outside the map"};
    }
  }
  for (std::size_t i = 0; i < c.targets.size(); ++i) {
    if (!inside_map(c.targets[i], p)) return Error{"liu swarm: target " + std::to_string(i) + " is outside the map"};
  }
  if (c.prior != LiuPrior::kUniform) {
    if (check_component(GaussianComponent{0.0, 0.0, c.prior_sigma_cells, c.prior_sigma_cells, 0.0, c.prior_weight})) {
      return Error{"liu swarm: prior_sigma_cells must be > 0 and prior_weight >= 0"};
    }
    if (c.prior == LiuPrior::kWrong) {
      for (const Vec2& v : c.wrong_prior_centres) {
        if (!inside_map(v, p)) return Error{"liu swarm: a wrong-prior centre is outside the map"};
      }
    }
  }
  return std::nullopt;
}


}  // namespace

void mower_advance(LiuMower& m, LiuUav& uav, double dt_s, const LiuParams& p) {
  const double l = p.mower_step_mps;
  if (m.climbing) {
    uav = advance_uav(uav, Vec2{0.0, m.dy * l}, dt_s, p);
    if ((m.dy > 0 && uav.position.y >= m.climb_to_y) || (m.dy < 0 && uav.position.y <= m.climb_to_y)) {
      uav.position.y = m.climb_to_y;
      m.climbing = false;
    }
    return;
  }
  uav = advance_uav(uav, Vec2{m.dx * l, 0.0}, dt_s, p);  // Liu 2022 eq. (14): P += b l Δt
  if ((uav.velocity.x > 0.0) == (m.dx > 0)) return;
  m.dx = -m.dx;  // b reversed at the border (advance_uav reflected the position)
  const int32_t row = cell_of(uav.position, p).y;
  for (int attempt = 0; attempt < 2; ++attempt) {
    if (m.lane.contains(Cell{m.lane.x0, row + m.dy})) {
      m.climbing = true;
      m.climb_to_y = (row + m.dy + 0.5) * p.cell_size_m;
      return;
    }
    m.dy = -m.dy;
  }
  // One-row lane: back along the row, exactly Liu 2022 eq. (14).
}

std::string_view to_string(LiuPolicy p) {
  switch (p) {
    case LiuPolicy::kEsustpm: return "ESUSTPM";
    case LiuPolicy::kLawnmower: return "mower";
    case LiuPolicy::kRandom: return "random";
    case LiuPolicy::kBoids: return "Boids";
    case LiuPolicy::kGuidedBoids: return "guided Boids";
    case LiuPolicy::kEsustpmDisperse: return "ESUSTPM-disperse";
  }
  return "?";
}

std::string_view to_string(LiuPrior p) {
  switch (p) {
    case LiuPrior::kUniform: return "uniform";
    case LiuPrior::kAccurate: return "accurate";
    case LiuPrior::kWrong: return "wrong";
  }
  return "?";
}

std::vector<double> liu_prior_map(const LiuSwarmConfig& config) {
  const LiuParams& p = config.params;
  if (config.prior == LiuPrior::kUniform) {
    return std::vector<double>(static_cast<std::size_t>(std::max(p.grid_width, 0)) *
                                   static_cast<std::size_t>(std::max(p.grid_height, 0)),
                               p.initial_probability);
  }
  const std::vector<Vec2>& centres = config.prior == LiuPrior::kAccurate ? config.targets : config.wrong_prior_centres;
  std::vector<GaussianComponent> components;
  for (const Vec2& v : centres) {
    const Cell c = cell_of(v, p);
    components.push_back({c.x + 0.5, c.y + 0.5, config.prior_sigma_cells, config.prior_sigma_cells, 0.0,
                          config.prior_weight});  // Liu 2022 eq. (1), Liu 2022 eq. (2), ρ = 0, σ1 = σ2 = σ0
  }
  return gaussian_mixture_prior(p.grid_width, p.grid_height, components);
}

namespace {

// The indices of the targets in each cell.
std::vector<std::vector<std::size_t>> targets_by_cell(const LiuSwarmConfig& config, int32_t w, int32_t h) {
  const LiuParams& p = config.params;
  std::vector<std::vector<std::size_t>> targets_in(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  for (std::size_t t = 0; t < config.targets.size(); ++t) {
    targets_in[cell_index(cell_of(config.targets[t], p), w)].push_back(t);
  }
  return targets_in;
}

// UAVs and their start velocities, the mowers' lanes and each UAV's stream.
struct LiuFleet {
  std::vector<LiuUav> uavs;
  std::vector<LiuMower> mowers;
  std::vector<Rng> rng;
};

LiuFleet launch_fleet(const LiuSwarmConfig& config, uint64_t seed, int32_t w, int32_t h) {
  const LiuParams& p = config.params;
  const std::size_t n = p.uav_count;
  const bool mower = config.policy == LiuPolicy::kLawnmower;
  LiuFleet f;
  f.uavs.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (mower) {
      const Rect lane = lawnmower_lane(static_cast<uint32_t>(i), static_cast<uint32_t>(n), w, h);
      f.mowers.push_back(LiuMower{lane});
      f.uavs[i].position = cell_centre(lawnmower_start(lane).cell, p.cell_size_m);
    } else {
      f.uavs[i].position = config.starts[i];
    }
    f.rng.emplace_back(stream_seed(seed, "liu-uav", static_cast<uint32_t>(i)));
    if (!mower && config.start_velocity == LiuStartVelocity::kRandomHeading) {
      const Vec2 d = random_direction(f.rng[i]);  // Liu 2022 eq. (12)
      f.uavs[i].velocity = Vec2{d.x * p.max_speed_mps, d.y * p.max_speed_mps};
    }
  }
  return f;
}

// Decisions from the state at the start of the cycle, all UAVs at once.
void decide_velocities(const LiuSwarmConfig& config, LiuFleet& f, const TpmLookup& lookup,
                       std::vector<LiuUav>& others) {
  const LiuParams& p = config.params;
  const std::size_t n = f.uavs.size();
  std::vector<Vec2> velocity(n);
  for (std::size_t i = 0; i < n; ++i) {
    others.clear();
    for (std::size_t j = 0; j < n; ++j) {
      if (j != i) others.push_back(f.uavs[j]);
    }
    LiuMove move;
    switch (config.policy) {
      case LiuPolicy::kEsustpm:
        move = esustpm_step(f.uavs[i], others, lookup, p);
        break;
      case LiuPolicy::kRandom:
        move = random_search_step(f.uavs[i], f.rng[i], p);
        break;
      case LiuPolicy::kBoids:
        move = boids_step(f.uavs[i], others, p);
        break;
      case LiuPolicy::kGuidedBoids:
        move = boids_guided_step(f.uavs[i], others, lookup, p);
        break;
      case LiuPolicy::kEsustpmDisperse:
        move = esustpm_disperse_step(f.uavs[i], others, lookup, p);
        break;
      case LiuPolicy::kLawnmower:
        break;
    }
    velocity[i] = move.velocity;
  }
  for (std::size_t i = 0; i < n; ++i) f.uavs[i].velocity = velocity[i];
}

// What a run's cells hold and have shown: the targets per cell, the TPM, the
// confirmed (latched) cells and the sensor's stream.
struct LiuSearchState {
  const std::vector<std::vector<std::size_t>>& targets_in;
  TargetProbabilityMap& tpm;
  std::vector<uint8_t>& latched;
  Rng& sensor;
};

// A UAV entered cell `now` in `cycle`: one observation, and a confirmation if the TPM passes θ.
void observe_cell(const LiuSwarmConfig& config, LiuSearchState& st, Cell now, uint32_t cycle, LiuSwarmResult& out) {
  const LiuParams& p = config.params;
  const std::size_t k = cell_index(now, p.grid_width);
  const bool target = !st.targets_in[k].empty();
  bool detected = target;  // Liu 2022 Algorithm 1: the branch is on the truth
  if (config.sensor == LiuSensor::kNoisy) {
    const double draw = st.sensor.uniform01();
    detected = target ? draw < p.p_detection : draw < p.p_false_alarm;
  }
  st.tpm.observe(now, detected);  // Liu 2022 eq. (4) or Liu 2022 eq. (5)
  ++out.observations;
  if (st.latched[k] == 0 && st.tpm.confirmed(now)) {  // "the TEP of a grid is more than the given value"
    st.latched[k] = 1;
    if (target) {
      for (const std::size_t t : st.targets_in[k]) out.confirmation_cycle[t] = cycle;
      out.targets_found += static_cast<uint32_t>(st.targets_in[k].size());
    } else {
      ++out.false_confirmations;
    }
  }
}

// Fly the cycle in Δt steps (Liu 2022 eq. (10), Liu 2022 eq. (11)); observe every cell entered.
void fly_cycle(const LiuSwarmConfig& config, LiuFleet& f, std::vector<Cell>& cell, VisitedCells& visited,
               LiuSearchState& st, uint32_t cycle, LiuSwarmResult& out) {
  const LiuParams& p = config.params;
  const bool mower = config.policy == LiuPolicy::kLawnmower;
  const auto substeps = static_cast<uint32_t>(std::max(1.0, std::round(p.cycle_s / p.dt_s)));
  const double dt = p.cycle_s / substeps;
  for (uint32_t s = 0; s < substeps; ++s) {
    for (std::size_t i = 0; i < f.uavs.size(); ++i) {
      if (mower) {
        mower_advance(f.mowers[i], f.uavs[i], dt, p);
      } else {
        f.uavs[i] = advance_uav(f.uavs[i], f.uavs[i].velocity, dt, p);
      }
      const Cell now = cell_of(f.uavs[i].position, p);
      if (now == cell[i]) continue;
      cell[i] = now;
      visited.visit(now);
      observe_cell(config, st, now, cycle, out);
    }
  }
}

void record_cycle(LiuSwarmResult& out, const TargetProbabilityMap& tpm, const VisitedCells& visited) {
  out.eu_per_cycle.push_back(environmental_uncertainty(tpm.values()));
  out.visited_per_cycle.push_back(visited.count());
  out.found_per_cycle.push_back(out.targets_found);
}

}  // namespace

Result<LiuSwarmResult> run_liu_swarm(const LiuSwarmConfig& config, uint64_t seed) {
  if (auto e = check_config(config)) return *e;
  const LiuParams& p = config.params;
  const int32_t w = p.grid_width;
  const int32_t h = p.grid_height;
  const Rect map{0, 0, w, h};
  const std::vector<double> prior = liu_prior_map(config);
  auto made = TargetProbabilityMap::from_map(map, prior, w, h, p);
  if (!made) return made.error();
  TargetProbabilityMap tpm = std::move(made.value());
  const std::vector<std::vector<std::size_t>> targets_in = targets_by_cell(config, w, h);

  LiuSwarmResult out;
  out.confirmation_cycle.assign(config.targets.size(), std::nullopt);
  std::vector<uint8_t> latched(targets_in.size(), 0);
  const TpmLookup lookup = [&](Cell c) -> std::optional<double> {
    if (!map.contains(c)) return std::nullopt;
    if (config.release_confirmed_cells && latched[cell_index(c, w)] != 0) return std::nullopt;
    return tpm.probability(c);
  };
  LiuFleet fleet = launch_fleet(config, seed, w, h);
  Rng sensor(stream_seed(seed, "liu-sensor", 0));
  LiuSearchState st{targets_in, tpm, latched, sensor};

  const std::size_t n = p.uav_count;
  VisitedCells visited(w, h);
  std::vector<Cell> cell(n);
  for (std::size_t i = 0; i < n; ++i) {
    cell[i] = cell_of(fleet.uavs[i].position, p);
    visited.visit(cell[i]);  // visited, but not observed: the UAV has not arrived there
  }
  record_cycle(out, tpm, visited);  // found: 0

  std::vector<LiuUav> others;
  others.reserve(n);
  for (uint32_t cycle = 1; cycle <= p.cycles; ++cycle) {
    if (config.policy != LiuPolicy::kLawnmower) decide_velocities(config, fleet, lookup, others);
    fly_cycle(config, fleet, cell, visited, st, cycle, out);
    record_cycle(out, tpm, visited);
  }

  if (!config.targets.empty() && out.targets_found == config.targets.size()) {
    uint32_t last = 0;
    for (const auto& c : out.confirmation_cycle) last = std::max(last, *c);
    out.all_found_cycle = last;
  }
  out.visited_cells = visited.count();
  out.final_eu = out.eu_per_cycle.back();
  out.final_tpm.assign(tpm.values().begin(), tpm.values().end());
  return out;
}

}  // namespace pheromesh::core
