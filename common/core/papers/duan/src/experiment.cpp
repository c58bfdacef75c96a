// Duan 2009 Sec. 4 second experiment (Duan 2009 Table 3) as a library; the readings are
// listed at the top of duan/experiment.hpp.
#include "pheromesh/duan/experiment.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <queue>
#include <span>
#include <string>
#include <utility>

#include "pheromesh/core/rng.hpp"

namespace pheromesh::core {

DuanOptimum duan_turn_constrained_optimum(const ThreatMesh& mesh, NodeId start, NodeId goal, double max_turn_rad) {
  constexpr int kDirs = ThreatMesh::kDirections;
  constexpr int kNoDir = kDirs;  // start state: no heading yet
  constexpr std::size_t kNoState = std::numeric_limits<std::size_t>::max();
  if (start >= mesh.node_count() || goal >= mesh.node_count()) return {};
  const std::size_t states = mesh.node_count() * (kDirs + 1);
  auto state = [](NodeId n, int d) {
    return static_cast<std::size_t>(n) * (kDirs + 1) + static_cast<std::size_t>(d);
  };
  std::vector<double> dist(states, std::numeric_limits<double>::infinity()), len(states, 0.0);
  std::vector<std::size_t> parent(states, kNoState);
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  dist[state(start, kNoDir)] = 0.0;
  q.push({0.0, state(start, kNoDir)});
  while (!q.empty()) {
    const auto [c, s] = q.top();
    q.pop();
    if (c > dist[s]) continue;
    const auto n = static_cast<NodeId>(s / (kDirs + 1));
    const int in = static_cast<int>(s % (kDirs + 1));
    if (n == goal) {
      DuanOptimum out{true, c, len[s], {}};
      for (std::size_t p = s; p != kNoState; p = parent[p]) out.nodes.push_back(static_cast<NodeId>(p / (kDirs + 1)));
      std::reverse(out.nodes.begin(), out.nodes.end());
      return out;
    }
    for (int d = 0; d < kDirs; ++d) {
      const NodeId u = mesh.neighbour(n, d);
      if (u == kNoNode) continue;
      if (in != kNoDir) {
        // Duan 2009 Fig. 4: the turn at n from the incoming edge to n -> u.
        const NodeId prev = mesh.neighbour(n, (in + kDirs / 2) % kDirs);
        if (!turn_allowed(mesh.position(prev), mesh.position(n), mesh.position(u), max_turn_rad)) continue;
      }
      const std::size_t t = state(u, d);
      const double nc = c + mesh.edge_cost(n, d);  // Duan 2009 eq. (3)
      if (nc < dist[t]) {
        dist[t] = nc;
        len[t] = len[s] + mesh.edge_length_km(n, d);
        parent[t] = s;
        q.push({nc, t});
      }
    }
  }
  return {};
}

double duan_last_improvement(const std::vector<double>& history) {
  std::size_t last = 0;
  for (std::size_t k = 1; k < history.size(); ++k) {
    if (history[k] < history[k - 1]) last = k;
  }
  return static_cast<double>(last + 1);
}

std::vector<std::vector<EtaCandidate>> duan_eta_candidates(const std::vector<PathResult>& results,
                                                           const std::vector<double>& offset_km) {
  std::vector<std::vector<EtaCandidate>> c(results.size());
  for (std::size_t i = 0; i < results.size(); ++i) {
    for (const auto& t : results[i].candidates) c[i].push_back({offset_km[i] + t.length_km, t.cost});
  }
  return c;
}

namespace {

bool all_found(const std::vector<PathResult>& r) {
  return std::all_of(r.begin(), r.end(), [](const PathResult& p) { return p.found; });
}

// Duan 2009 eq. (4), Duan 2009 eq. (5), Duan 2009 eq. (6), Duan 2009 eq. (7), Duan 2009 eq. (8): T_a = min S over 4
// candidates per UAV.
Result<EtaPlan> team_eta(const std::vector<PathResult>& results, const std::vector<double>& offset_km,
                         const Duan2009Scenario& sc, const DuanTable3Options& options) {
  return all_found(results) ? coordinate_eta(duan_eta_candidates(results, offset_km), sc.speeds, options.eta)
                            : Result<EtaPlan>(Error{"a colony found no path"});
}

std::vector<DuanOptimum> duan_optima(const Duan2009Scenario& sc) {
  std::vector<DuanOptimum> optimum;
  const ThreatMesh mesh(sc.mesh, sc.threats);
  for (const Duan2009Uav& uav : sc.uavs) {
    optimum.push_back(duan_turn_constrained_optimum(mesh, *mesh.nearest_node(uav.start), *mesh.nearest_node(uav.target),
                                                    sc.aco.max_turn_rad));
  }
  return optimum;
}

// The planned candidates of each UAV, and whether one is its shortest walk.
void record_planned(DuanTable3Run& run, const std::vector<PathResult>& planned,
                    const std::vector<DuanOptimum>& optimum) {
  for (std::size_t i = 0; i < run.uavs.size(); ++i) {
    DuanTable3Uav& u = run.uavs[i];
    u.planned = planned[i];
    u.holds_shortest = std::any_of(planned[i].candidates.begin(), planned[i].candidates.end(),
                                   [&](const auto& t) { return t.length_km <= optimum[i].length_km + 1e-6; });
  }
}

// What each UAV flies at T_a: its chosen candidate and speed.
void record_flown(DuanTable3Run& run, const std::vector<PathResult>& planned, const std::vector<DuanOptimum>& optimum) {
  const EtaPlan& plan = run.plan;
  for (std::size_t i = 0; i < run.uavs.size(); ++i) {
    DuanTable3Uav& u = run.uavs[i];
    const Trajectory& t = planned[i].candidates[plan.chosen[i]];
    u.length_km = t.length_km;
    u.speed_mps = plan.speed_mps[i];
    u.cost_over_optimum = t.cost / optimum[i].cost;
    u.last_improvement = duan_last_improvement(planned[i].best_cost_history);
    u.flown = t.nodes;
  }
}

// Where a UAV replans from: the distance from its position to that node and
// the rest of its old trajectory from there.
struct Continuation {
  double offset_km = 0.0;
  std::vector<NodeId> rest;
};

// A mesh walk: the first node at or past the UAV's position; never the goal itself.
Continuation continue_on_walk(const ThreatMesh& mesh, const std::vector<NodeId>& nodes, double at_km, DuanTable3Uav& u,
                              UavTask& task) {
  Continuation c;
  double cum = 0.0;
  std::size_t k = 0;
  while (k + 2 < nodes.size() && cum < at_km) {
    cum += mesh.edge_length_km(nodes[k], mesh.direction(nodes[k], nodes[k + 1]));
    ++k;
  }
  c.offset_km = std::max(0.0, cum - at_km);
  u.flown_km = cum;
  task = UavTask{nodes[k], task.goal, k > 0 ? std::optional<NodeId>(nodes[k - 1]) : std::nullopt};
  c.rest.assign(nodes.begin() + static_cast<std::ptrdiff_t>(k), nodes.end());
  u.flown.resize(k + 1);
  return c;
}

// Line-of-sight trajectory (segments longer than a mesh edge): the UAV
// is at P on segment k; its "neighbouring node" (Step 3) is the mesh
// node nearest to the point one mesh spacing ahead of P, reached
// straight from P; the goal itself is never taken.
Continuation continue_on_segments(const ThreatMesh& mesh, const std::vector<NodeId>& nodes, double at_km,
                                  DuanTable3Uav& u, UavTask& task) {
  Continuation c;
  double cum = 0.0;
  std::size_t k = 0;
  auto seg = [&](std::size_t j) {
    const PointKm a = mesh.position(nodes[j]), b = mesh.position(nodes[j + 1]);
    return std::hypot(b.x - a.x, b.y - a.y);
  };
  while (k + 2 < nodes.size() && cum + seg(k) < at_km) cum += seg(k++);
  const PointKm a = mesh.position(nodes[k]), b = mesh.position(nodes[k + 1]);
  const double len = seg(k);
  const double along = std::min(at_km - cum, len);
  const double ahead = std::min(along + std::min(mesh.step_x_km(), mesh.step_y_km()), len);
  const PointKm p{a.x + along / len * (b.x - a.x), a.y + along / len * (b.y - a.y)};
  NodeId r = *mesh.nearest_node({a.x + ahead / len * (b.x - a.x), a.y + ahead / len * (b.y - a.y)});
  if (r == task.goal) r = nodes[k];
  const PointKm rp = mesh.position(r);
  c.offset_km = std::hypot(rp.x - p.x, rp.y - p.y);
  u.flown_km = cum + along + c.offset_km;
  u.flown.resize(k + 1);
  if (r != nodes[k]) u.flown.push_back(r);
  const std::size_t m = u.flown.size();
  task = UavTask{r, task.goal, m >= 2 ? std::optional<NodeId>(u.flown[m - 2]) : std::nullopt};
  c.rest.push_back(r);
  c.rest.insert(c.rest.end(), nodes.begin() + static_cast<std::ptrdiff_t>(k + 1), nodes.end());
  return c;
}

// Duan 2009 Sec. 2.5 Step 3: each UAV carries on to the next node of its
// trajectory ("a neighbouring node") and replans from there, Step 4: heading
// kept for the turn constraint. Returns each UAV's offset to that node.
std::vector<double> advance_to_replanning_nodes(const ThreatMesh& mesh, DuanTable3Run& run, std::vector<UavTask>& tasks,
                                                double popup_time_s) {
  std::vector<double> offset(run.uavs.size(), 0.0);
  for (std::size_t i = 0; i < run.uavs.size(); ++i) {
    DuanTable3Uav& u = run.uavs[i];
    const std::vector<NodeId> nodes = u.flown;  // a copy: u.flown is cut below
    const double at_km = run.plan.speed_mps[i] * popup_time_s / 1000.0;
    bool mesh_walk = true;
    for (std::size_t j = 1; j < nodes.size(); ++j) mesh_walk = mesh_walk && mesh.direction(nodes[j - 1], nodes[j]) >= 0;
    const Continuation c = mesh_walk ? continue_on_walk(mesh, nodes, at_km, u, tasks[i])
                                     : continue_on_segments(mesh, nodes, at_km, u, tasks[i]);
    offset[i] = c.offset_km;
    u.offset_km = offset[i];
    u.old_remaining_threat = polyline_cost(mesh, c.rest).threat;  // Duan 2009 eq. (2)
    run.old_threat_sum += u.old_remaining_threat;
  }
  return offset;
}

void record_replan(DuanTable3Run& run, const std::vector<PathResult>& replanned, const Result<EtaPlan>& plan2,
                   double popup_time_s) {
  for (std::size_t i = 0; i < run.uavs.size(); ++i) run.uavs[i].replanned = replanned[i];
  run.replan_eta_found = plan2.ok();
  if (!run.replan_eta_found) return;
  run.replan = plan2.value();
  run.eta_after_replan_s = popup_time_s + plan2->eta_s;
  for (std::size_t i = 0; i < run.uavs.size(); ++i) {
    DuanTable3Uav& u = run.uavs[i];
    const Trajectory& t = replanned[i].candidates[plan2->chosen[i]];
    u.length_after_replan_km = u.flown_km + t.length_km;
    u.replanned_nodes = t.nodes;
    run.new_threat_sum += t.threat_cost;
  }
}

// One Monte Carlo run: team planning, ETA, then the pop-ups and replanning.
DuanTable3Run duan_table3_run(const Duan2009Scenario& sc, const DuanTable3Options& options,
                              const std::vector<DuanOptimum>& optimum, uint64_t seed) {
  const std::size_t uav_count = sc.uavs.size();
  DuanTable3Run run;
  run.seed = seed;
  run.uavs.resize(uav_count);
  ThreatMesh mesh(sc.mesh, sc.threats);  // the colonies hold it: it outlives them
  std::vector<DuanColony> team;
  std::vector<UavTask> tasks;
  for (std::size_t i = 0; i < uav_count; ++i) {
    team.emplace_back(mesh, sc.aco, Rng(stream_seed(run.seed, "duan", static_cast<uint32_t>(i))));
    tasks.push_back({*mesh.nearest_node(sc.uavs[i].start), *mesh.nearest_node(sc.uavs[i].target), {}});
  }
  const std::vector<double> no_offset(uav_count, 0.0);
  // Duan 2009 Fig. 12: the colonies plan in lockstep, exchanging point pheromone.
  const auto planned = plan_team(team, tasks, [&](uint32_t) {
    std::vector<PathResult> now;
    for (const DuanColony& c : team) now.push_back(c.result());
    const auto eta = team_eta(now, no_offset, sc, options);
    run.eta_history.push_back(eta.ok() ? eta->eta_s : std::numeric_limits<double>::infinity());
  });
  const auto plan = team_eta(planned, no_offset, sc, options);
  record_planned(run, planned, optimum);
  run.eta_found = plan.ok();
  if (!run.eta_found) return run;
  run.plan = plan.value();
  record_flown(run, planned, optimum);

  // Duan 2009 Sec. 2.5 Steps 1-2: the pop-ups change the mesh costs.
  mesh.add_threats(sc.popups);
  const std::vector<double> offset = advance_to_replanning_nodes(mesh, run, tasks, options.popup_time_s);
  const auto replanned = plan_team(team, tasks);
  record_replan(run, replanned, team_eta(replanned, offset, sc, options), options.popup_time_s);
  return run;
}

}  // namespace

DuanTable3Result duan_table3(const Duan2009Scenario& sc, const DuanTable3Options& options,
                             const DuanProgress& progress) {
  DuanTable3Result out;
  out.optimum = duan_optima(sc);
  for (uint32_t r = 0; r < options.runs; ++r) {
    out.runs.push_back(duan_table3_run(sc, options, out.optimum, r + 1));
    if (progress) progress(r + 1, options.runs);
  }
  return out;
}

}  // namespace pheromesh::core
