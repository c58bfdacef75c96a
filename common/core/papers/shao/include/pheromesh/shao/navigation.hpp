// Shao 2020 Sec. 5, navigation via flocking and stigmergy: the leader's
// vector-pheromone step (Shao 2020 eq. (12), Shao 2020 eq. (13), Shao 2020 eq. (14), Shao 2020 eq. (15), Shao 2020 Algorithm 2), a scalar-pheromone leader
// for comparison, and the followers' modified Olfati-Saber flocking step
// (Shao 2020 eq. (17), Shao 2020 eq. (18), Shao 2020 eq. (19), Shao 2020 eq. (20), Shao 2020 eq. (21), Shao 2020 eq. (22), Shao 2020 eq. (23), Shao 2020 eq. (24)). Pure math; positions in [cell], velocities in [cell/tick],
// one tick = one iteration of the paper. A lattice cell c sits at the point
// (c.x, c.y); x grows east and y grows "north" as in aco.hpp.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/shao/aco.hpp"

namespace pheromesh::core {

// Direction of the gradient term of Shao 2020 eq. (19). Shao 2020 eq. (21) prints
// n_kj = (q_j - q_k)/..., i.e. towards neighbour j, which with φα(z) = 1/z > 0
// (Shao 2020 eq. (20)) attracts followers to each other, the more the closer they are.
// The sentence before Shao 2020 eq. (21) calls n_kj "the unit vector from the jth agent
// to the kth agent", i.e. away from j, which makes the term a separation
// (repulsion decaying with distance). The printed formula is the default.
enum class NeighbourGradient : uint8_t { TowardsNeighbour = 0, AwayFromNeighbour = 1 };

// Argument of the bump in Shao 2020 eq. (22). SigmaRange divides by r_σ = ‖r‖_σ as
// Olfati-Saber (2006) does, so a_kj falls to 0 exactly at the edge of N_k
// (‖q_j - q_k‖ = r). LiteralRange divides by r itself as Shao 2020 eq. (22) prints,
// so a_kj is already 0 from ‖q_j - q_k‖_σ >= r (distance ≈ 3.1 for r = 4,
// ε = 0.1), inside N_k.
enum class AdjacencyScale : uint8_t { SigmaRange = 0, LiteralRange = 1 };

// How "s_t = max_d s_d^t" (Shao 2020 Sec. 5.1.1, after Shao 2020 eq. (14)) picks the
// sector of the vector leader. A maximum of vectors needs an order the paper
// does not give. Norm takes the s_d of largest Euclidean norm (the strongest
// weighted gradient, whichever way it points: an obstacle's repulsion felt in
// a sector counts as much as a target's pull). Projection takes the s_d with
// the largest component along its own sector's bisector (the sector the
// field pulls the leader into most; a sector whose s_d points back out of it
// scores negative). Both move along s_d itself, Shao 2020 eq. (15).
enum class VectorSectorChoice : uint8_t { Norm = 0, Projection = 1 };

// How the scalar leader of Shao 2020 Fig. 10b (not specified in the paper) scores a
// sector from λTa τ_j + λTh ε_j + λTr σ_j over its known cells J(d).
enum class ScalarSectorScore : uint8_t { Mean = 0, Sum = 1, Max = 2 };

// How far the scalar leader moves per iteration along its sector's bisector:
// ρ as the vector leader (Shao 2020 eq. (15)), or one lattice step (1 cell on
// an axis, √2 on a diagonal) as the UAVs of Shao 2020 Sec. 4 move.
enum class ScalarLeaderStep : uint8_t { Rho = 0, Lattice = 1 };

// Shao 2020 Table 2 values unless stated otherwise.
struct ShaoNavParams {
  double leader_sensor_radius = 5.0;  // sensorLD [cell]
  double rho = 2.0;                   // ρ, leader speed coefficient of Shao 2020 eq. (15) [cell/tick]
  double lambda_target = 1.0;         // λTa, Shao 2020 eq. (14)
  double lambda_obstacle = -0.3;      // λTh
  double lambda_path = 0.3;           // λTr
  double epsilon = 0.1;               // ε of the σ-norm, Shao 2020 eq. (18), in (0, 1)
  double h = 0.5;                     // h of the bump ρh, Shao 2020 eq. (23), in (0, 1)
  double c1 = 0.6;                    // leader position weight, Shao 2020 eq. (19) [1/tick]
  double c2 = 0.4;                    // leader velocity weight, Shao 2020 eq. (19)
  // r of Shao 2020 eq. (17) [cell]. Shao 2020 Sec. 5 gives no value; followers are the UAVs that run
  // the detection algorithm of Shao 2020 Sec. 4 once the leader has arrived (Shao 2020 Algorithm 3),
  // whose sensor radius is SD = 4 (Shao 2020 Table 1), smaller than the leader's 5.
  double follower_range = 4.0;
  NeighbourGradient neighbour_gradient = NeighbourGradient::TowardsNeighbour;
  AdjacencyScale adjacency_scale = AdjacencyScale::SigmaRange;
  VectorSectorChoice vector_choice = VectorSectorChoice::Norm;
  ScalarSectorScore scalar_score = ScalarSectorScore::Mean;
  ScalarLeaderStep scalar_step = ScalarLeaderStep::Rho;
};

// Target, obstacle and path pheromone at a cell; nullopt if unknown (no tile).
using PheromoneLookup = std::function<std::optional<std::array<float, 3>>(Cell)>;

inline constexpr int kNavSectorCount = 8;
using SectorVectors = std::array<Eigen::Vector2d, kNavSectorCount>;
// Eigen vectors are not zeroed by default construction.
inline SectorVectors zero_sector_vectors() {
  SectorVectors a;
  a.fill(Eigen::Vector2d::Zero());
  return a;
}

struct LeaderStep {
  Eigen::Vector2d q = Eigen::Vector2d::Zero();  // q_{t+1} [cell]
  Eigen::Vector2d v = Eigen::Vector2d::Zero();  // v_{t+1} [cell/tick]; 0 when nothing to follow
  std::optional<Heading> sector;                // chosen sector d; nullopt: no move from pheromones
  // Vector leader: s_d of Shao 2020 eq. (14). Scalar leader: zero.
  SectorVectors sector_sums = zero_sector_vectors();
  // Selection criterion per sector: ‖s_d‖ or s_d·u_d (vector leader, see
  // VectorSectorChoice), the mean / sum / max of the λ-weighted scalar values
  // (scalar leader, see ScalarSectorScore; 0 where sector_cells is 0), or
  // ‖s_d‖ (gradient leader).
  std::array<double, kNavSectorCount> sector_scores{};
  std::array<int, kNavSectorCount> sector_cells{};  // known cells used per sector
  bool heading_to_centre = false;  // Shao 2020 Algorithm 2 line 2 ("go there") drove this step
  bool at_centre = false;          // q_{t+1} is the centre: the leader becomes a follower
};

// Sector (Heading index 0..7) of a non-zero offset: the heading whose angle
// is within ±22.5° of the offset's bearing, a boundary bearing going to the
// counter-clockwise sector. Same sectors as the ACO of Shao 2020 Sec. 4.
Heading nav_sector_of(const Eigen::Vector2d& offset);

// One leader step with vector pheromones, Shao 2020 eq. (12), Shao 2020 eq. (13), Shao 2020 eq. (14), Shao 2020 eq. (15).
LeaderStep leader_vector_step(const Eigen::Vector2d& q, const PheromoneLookup& pheromones,
                              const ShaoNavParams& p);
// Our baseline reading of the scalar-pheromone leader of Shao 2020 Fig. 10b.
LeaderStep leader_scalar_step(const Eigen::Vector2d& q, const PheromoneLookup& pheromones,
                              const ShaoNavParams& p);
// Our variant "gradient" (not the paper's): the s_d of Shao 2020 eq. (12), Shao 2020 eq. (13), Shao 2020 eq. (14) are
// summed over all eight sectors instead of taking one sector's, and the
// leader moves ρ along that resultant, the λ-weighted pheromone gradient
// over the whole sensor disk. No sector is chosen (sector stays nullopt).
LeaderStep leader_gradient_step(const Eigen::Vector2d& q, const PheromoneLookup& pheromones, const ShaoNavParams& p);
// Our variant "pull" (not the paper's): the sum of the s_d that pull the
// leader into their own sector (s_d·u_d > 0 along the sector's bisector u_d,
// the candidates of VectorSectorChoice::Projection), ρ along it. The s_d of a
// sector whose pheromone pushes the leader back out of it (an obstacle's,
// under λTh < 0) is left out; no sector pulls: the leader stays.
LeaderStep leader_pull_step(const Eigen::Vector2d& q, const PheromoneLookup& pheromones, const ShaoNavParams& p);

// Shao 2020 Algorithm 2 line 1: the centre of the target region is within sensorLD.
bool leader_reaches_centre(const Eigen::Vector2d& q, const Eigen::Vector2d& centre, const ShaoNavParams& p);

// Vector and Scalar are Shao 2020 Fig. 10's two leaders; Gradient and Pull are our variants.
enum class LeaderPheromones : uint8_t { Vector = 0, Scalar = 1, Gradient = 2, Pull = 3 };
// Shao 2020 Algorithm 2: go towards the centre (at most ρ per tick) once it is within
// sensorLD, else one pheromone step of the chosen kind.
LeaderStep leader_algorithm2_step(const Eigen::Vector2d& q, const Eigen::Vector2d& centre,
                                  const PheromoneLookup& pheromones, const ShaoNavParams& p,
                                  LeaderPheromones kind = LeaderPheromones::Vector);

struct FollowerState {
  Eigen::Vector2d q = Eigen::Vector2d::Zero();  // [cell]
  Eigen::Vector2d v = Eigen::Vector2d::Zero();  // [cell/tick]
};

struct FollowerStep {
  Eigen::Vector2d q = Eigen::Vector2d::Zero();  // q_{t+1}, Shao 2020 eq. (24) [cell]
  Eigen::Vector2d v = Eigen::Vector2d::Zero();  // v_{t+1}, Shao 2020 eq. (19) [cell/tick]
  // The three parts of Shao 2020 eq. (19), v = gradient + consensus + leader.
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();   // Σ φα(‖q_j - q_k‖_σ) n_kj
  Eigen::Vector2d consensus = Eigen::Vector2d::Zero();  // Σ a_kj (v_j - v_k)
  Eigen::Vector2d leader = Eigen::Vector2d::Zero();     // -c1 (q_k - q_L) - c2 (v_k - v_L)
  int neighbour_count = 0;                              // |N_k|
};

// One follower step, Shao 2020 eq. (17), Shao 2020 eq. (18), Shao 2020 eq. (19), Shao 2020 eq. (20), Shao 2020 eq. (21), Shao 2020 eq. (22), Shao 2020 eq. (23), Shao 2020 eq. (24). `others` holds the other followers (not
// self, not the leader); N_k is taken from them by Shao 2020 eq. (17). The leader's
// state is always known to the follower (it enters only through c1, c2).
FollowerStep follower_step(const FollowerState& self, std::span<const FollowerState> others,
                           const FollowerState& leader, const ShaoNavParams& p);

// ‖z‖_σ = (√(1 + ε‖z‖²) - 1)/ε, Shao 2020 eq. (18).
double sigma_norm(const Eigen::Vector2d& z, double epsilon);
// ρh(z) of Shao 2020 eq. (23).
double bump(double z, double h);
// φα(z) = 1/z, Shao 2020 eq. (20); +inf at 0.
double phi_alpha(double z);

}  // namespace pheromesh::core
