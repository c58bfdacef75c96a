// Parameters of Shao 2020 (Shao 2020 Table 1 holds the paper's values).
#pragma once

#include <cstdint>

namespace pheromesh::core {

struct ShaoLayerParams {
  double e_tau = 0.2;      // Eτ, evaporation of target pheromone, [0,1)
  double g_tau = 0.2;      // Gτ, diffusion of target pheromone, [0,1)
  double d_tau = 1.0;      // dτ, target deposit per iteration
  double e_eps = 0.2;      // Eε
  double g_eps = 0.2;      // Gε
  double d_eps = 1.0;      // dε
  double sigma0 = 2.0;     // σ0, initial (and maximum) path pheromone
  double sigma_min = 0.1;  // σmin
  double d0 = 4.0;         // D0, range of influence of a UAV on path pheromone [cell]
  double q = 1.0;          // Q, attenuation coefficient
};

struct ShaoAcoParams {
  double alpha = 1.0;             // α, pheromone exponent (not given in the paper)
  double beta = 1.0;              // β, physical-cost exponent (not given in the paper)
  double lambda_target = 1.0;     // λTa
  double lambda_obstacle = -0.3;  // λTh
  double lambda_path = 0.3;       // λTr
  double sensor_radius = 4.0;     // SD [cell]
  double random_fraction = 0.3;   // probability that a UAV is in the random sub-group at a step
  uint32_t revisit_period = 500;  // T [tick]
};

}  // namespace pheromesh::core
