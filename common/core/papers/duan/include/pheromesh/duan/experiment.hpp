// Duan, Zhang, Wu, Ma 2009, Duan 2009 Sec. 4 second experiment (Duan 2009 Table 3, Duan 2009 Fig. 15, Duan 2009 Fig.
// 16, Duan 2009 Fig. 17, Duan 2009 Fig. 18, Duan 2009 Fig. 19) as a library: the per-UAV optimum under the turn
// constraint (a Dijkstra over node x heading) and the Monte Carlo loop behind `pheromesh experiment duan-table3` — team
// planning, ETA, the Duan 2009 Table 4 pop-ups and replanning — returning plain numbers. The CLI only formats them.
//
// Reading of the paper for the loop (the planning itself is read in
// duan_aco.cpp):
//  * Duan 2009 Table 4 gives no time for the pop-ups; they appear popup_time_s after
//    take-off (30 s by default, see DuanTable3Options).
//  * Replanning (Duan 2009 Sec. 2.5 Steps 1-4): each UAV carries on to the first node of its
//    trajectory at or past its position at that time (never the goal itself)
//    and replans from there with a fresh team of colonies, the node before it
//    kept as heading for the turn constraint. The new ETA counts the stretch
//    to that node (offset) at the new speed.
//  * Trajectories of the line_of_sight planners (DuanPlanner::LineOfSight and
//    DuanPlanner::SafeLineOfSight, ours) have segments longer than a mesh edge: such a UAV replans from the mesh
//    node nearest to the point one node spacing ahead of its position on its
//    segment (never its target), reached straight from where it is.
//  * Random numbers: run r (0-based) uses seed r + 1; colony i draws from
//    stream_seed(seed, "duan", i), the same colony (and stream) for planning
//    and replanning.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "pheromesh/duan/aco.hpp"

namespace pheromesh::core {

// The cheapest walk under Duan 2009 eq. (3) edge costs that never turns by more than
// max_turn_rad (Duan 2009 Fig. 4): Dijkstra over (node, incoming direction).
// The first step from start may go in any direction. It ignores other UAVs
// (no point pheromone), so it is a lower bound for what one colony can find.
struct DuanOptimum {
  bool found = false;
  double cost = std::numeric_limits<double>::infinity();  // Σ J of Duan 2009 eq. (3)
  double length_km = 0.0;                                 // [km]
  std::vector<NodeId> nodes;                              // start ... goal; empty if not found
};
DuanOptimum duan_turn_constrained_optimum(const ThreatMesh& mesh, NodeId start, NodeId goal, double max_turn_rad);

// Last iteration (1-based) at which the best-so-far cost improved; 1 if it
// never improved after the first iteration (or the history is empty).
double duan_last_improvement(const std::vector<double>& best_cost_history);

// Candidates of each UAV as ETA input, lengths counted from offset_km[i]
// (the stretch a UAV flies before its trajectory starts).
std::vector<std::vector<EtaCandidate>> duan_eta_candidates(const std::vector<PathResult>& results,
                                                           const std::vector<double>& offset_km);

struct DuanTable3Options {
  uint32_t runs = 10;
  // Pop-ups appear at this time after take-off (the paper gives no time; Fig.
  // 18 only shows the UAVs "marching"). 30 s ≈ 9 km flown: in the paper's
  // scenario every UAV is still at least 5 km outside the pop-up ranges.
  double popup_time_s = 30.0;  // [s]
  // How T_a is chosen from S (Duan 2009 Fig. 6's min S by default; the text of Duan 2009 Sec. 3.3 also
  // speaks of the T_a "that minimizes the total coordination cost", Duan 2009 eq. (8)).
  EtaOptions eta;
};

// One UAV in one run. Fields after `planned` are set only when the run had a
// common arrival time (DuanTable3Run::eta_found); the replanned ones only when
// the replanned team had one too (replan_eta_found).
struct DuanTable3Uav {
  PathResult planned;            // plan_team result (candidates, Duan 2009 Fig. 17 history)
  bool holds_shortest = false;   // a candidate is as short as the optimum's walk
  double length_km = 0.0;        // candidate flown at T_a
  double speed_mps = 0.0;        // V = L / T_a
  double cost_over_optimum = 0.0;  // J / J*
  double last_improvement = 0.0;   // duan_last_improvement of its history
  std::vector<NodeId> flown;       // planned trajectory up to the replanning node
  double flown_km = 0.0;           // length of `flown`
  double offset_km = 0.0;          // from the position at popup_time_s to the replanning node
  double old_remaining_threat = 0.0;  // Σ J_threat of the rest of the old trajectory under the pop-ups
  PathResult replanned;
  double length_after_replan_km = 0.0;  // flown_km + replanned candidate
  std::vector<NodeId> replanned_nodes;  // replanned candidate flown
};

struct DuanTable3Run {
  uint64_t seed = 0;
  bool eta_found = false;  // all colonies found a path and S ≠ ∅
  EtaPlan plan;
  // T_a (min S) of the candidates held after each planning iteration; +inf
  // while a colony has none or S is empty. Its last entry is plan.eta_s.
  std::vector<double> eta_history;
  bool replan_eta_found = false;
  EtaPlan replan;  // eta_s counted from the replanning instant
  double eta_after_replan_s = 0.0;  // from take-off: popup_time_s + replan.eta_s
  double old_threat_sum = 0.0;      // Σ_i old_remaining_threat
  double new_threat_sum = 0.0;      // Σ_i J_threat of the replanned candidates flown
  std::vector<DuanTable3Uav> uavs;
};

struct DuanTable3Result {
  std::vector<DuanOptimum> optimum;  // per UAV, on the static mesh (the same for every run)
  std::vector<DuanTable3Run> runs;
};

// Called after each run: (runs done, runs in total).
using DuanProgress = std::function<void(uint32_t done, uint32_t total)>;

// Duan 2009 Table 3: for seeds 1..runs, plan_team on the scenario's mesh,
// coordinate_eta (T_a = min S), add the pop-ups and replan. Every UAV of
// scenario.uavs takes part.
DuanTable3Result duan_table3(const Duan2009Scenario& scenario, const DuanTable3Options& options,
                             const DuanProgress& progress = {});

}  // namespace pheromesh::core
