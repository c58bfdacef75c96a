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

}  // namespace

DuanTable3Result duan_table3(const Duan2009Scenario& sc, const DuanTable3Options& options,
                             const DuanProgress& progress) {
  const std::size_t uav_count = sc.uavs.size();
  DuanTable3Result out;
  {
    const ThreatMesh mesh(sc.mesh, sc.threats);
    for (std::size_t i = 0; i < uav_count; ++i) {
      out.optimum.push_back(duan_turn_constrained_optimum(mesh, *mesh.nearest_node(sc.uavs[i].start),
                                                          *mesh.nearest_node(sc.uavs[i].target), sc.aco.max_turn_rad));
    }
  }

  for (uint32_t r = 0; r < options.runs; ++r) {
    DuanTable3Run run;
    run.seed = r + 1;
    run.uavs.resize(uav_count);
    ThreatMesh mesh(sc.mesh, sc.threats);
    std::vector<DuanColony> team;
    std::vector<UavTask> tasks;
    for (std::size_t i = 0; i < uav_count; ++i) {
      team.emplace_back(mesh, sc.aco, Rng(stream_seed(run.seed, "duan", static_cast<uint32_t>(i))));
      tasks.push_back({*mesh.nearest_node(sc.uavs[i].start), *mesh.nearest_node(sc.uavs[i].target), {}});
    }
    // Duan 2009 Fig. 12: the colonies plan in lockstep, exchanging point pheromone.
    const auto planned = plan_team(team, tasks, [&](uint32_t) {
      std::vector<PathResult> now;
      for (const DuanColony& c : team) now.push_back(c.result());
      const auto eta = all_found(now) ? coordinate_eta(duan_eta_candidates(now, std::vector<double>(uav_count, 0.0)),
                                                       sc.speeds, options.eta)
                                      : Result<EtaPlan>(Error{"a colony found no path"});
      run.eta_history.push_back(eta.ok() ? eta->eta_s : std::numeric_limits<double>::infinity());
    });
    // Duan 2009 eq. (4), Duan 2009 eq. (5), Duan 2009 eq. (6), Duan 2009 eq. (7), Duan 2009 eq. (8): T_a = min S over 4 candidates per UAV.
    const auto plan =
        all_found(planned)
            ? coordinate_eta(duan_eta_candidates(planned, std::vector<double>(uav_count, 0.0)), sc.speeds, options.eta)
            : Result<EtaPlan>(Error{"a colony found no path"});
    for (std::size_t i = 0; i < uav_count; ++i) {
      DuanTable3Uav& u = run.uavs[i];
      u.planned = planned[i];
      u.holds_shortest = std::any_of(planned[i].candidates.begin(), planned[i].candidates.end(), [&](const auto& t) {
        return t.length_km <= out.optimum[i].length_km + 1e-6;
      });
    }
    run.eta_found = plan.ok();
    if (!run.eta_found) {
      out.runs.push_back(std::move(run));
      if (progress) progress(r + 1, options.runs);
      continue;
    }
    run.plan = plan.value();
    for (std::size_t i = 0; i < uav_count; ++i) {
      DuanTable3Uav& u = run.uavs[i];
      const Trajectory& t = planned[i].candidates[plan->chosen[i]];
      u.length_km = t.length_km;
      u.speed_mps = plan->speed_mps[i];
      u.cost_over_optimum = t.cost / out.optimum[i].cost;
      u.last_improvement = duan_last_improvement(planned[i].best_cost_history);
      u.flown = t.nodes;
    }

    // Duan 2009 Sec. 2.5 Steps 1-2: the pop-ups change the mesh costs; Step 3: each
    // UAV carries on to the next node of its trajectory ("a neighbouring node")
    // and replans from there, Step 4: heading kept for the turn constraint.
    mesh.add_threats(sc.popups);
    std::vector<double> offset(uav_count, 0.0);
    for (std::size_t i = 0; i < uav_count; ++i) {
      DuanTable3Uav& u = run.uavs[i];
      const std::vector<NodeId> nodes = u.flown;  // a copy: u.flown is cut below
      const double at_km = plan->speed_mps[i] * options.popup_time_s / 1000.0;
      bool mesh_walk = true;
      for (std::size_t j = 1; j < nodes.size(); ++j)
        mesh_walk = mesh_walk && mesh.direction(nodes[j - 1], nodes[j]) >= 0;
      std::vector<NodeId> rest;
      if (mesh_walk) {
        // First node at or past the UAV's position; never the goal itself.
        double cum = 0.0;
        std::size_t k = 0;
        while (k + 2 < nodes.size() && cum < at_km) {
          cum += mesh.edge_length_km(nodes[k], mesh.direction(nodes[k], nodes[k + 1]));
          ++k;
        }
        offset[i] = std::max(0.0, cum - at_km);
        u.flown_km = cum;
        tasks[i] = UavTask{nodes[k], tasks[i].goal, k > 0 ? std::optional<NodeId>(nodes[k - 1]) : std::nullopt};
        rest.assign(nodes.begin() + static_cast<std::ptrdiff_t>(k), nodes.end());
        u.flown.resize(k + 1);
      } else {
        // Line-of-sight trajectory (segments longer than a mesh edge): the UAV
        // is at P on segment k; its "neighbouring node" (Step 3) is the mesh
        // node nearest to the point one mesh spacing ahead of P, reached
        // straight from P; the goal itself is never taken.
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
        if (r == tasks[i].goal) r = nodes[k];
        const PointKm rp = mesh.position(r);
        offset[i] = std::hypot(rp.x - p.x, rp.y - p.y);
        u.flown_km = cum + along + offset[i];
        u.flown.resize(k + 1);
        if (r != nodes[k]) u.flown.push_back(r);
        const std::size_t m = u.flown.size();
        tasks[i] = UavTask{r, tasks[i].goal, m >= 2 ? std::optional<NodeId>(u.flown[m - 2]) : std::nullopt};
        rest.push_back(r);
        rest.insert(rest.end(), nodes.begin() + static_cast<std::ptrdiff_t>(k + 1), nodes.end());
      }
      u.offset_km = offset[i];
      u.old_remaining_threat = polyline_cost(mesh, rest).threat;  // Duan 2009 eq. (2)
      run.old_threat_sum += u.old_remaining_threat;
    }
    const auto replanned = plan_team(team, tasks);
    const auto plan2 = all_found(replanned)
                           ? coordinate_eta(duan_eta_candidates(replanned, offset), sc.speeds, options.eta)
                           : Result<EtaPlan>(Error{"a colony found no path"});
    for (std::size_t i = 0; i < uav_count; ++i) run.uavs[i].replanned = replanned[i];
    run.replan_eta_found = plan2.ok();
    if (run.replan_eta_found) {
      run.replan = plan2.value();
      run.eta_after_replan_s = options.popup_time_s + plan2->eta_s;
      for (std::size_t i = 0; i < uav_count; ++i) {
        DuanTable3Uav& u = run.uavs[i];
        const Trajectory& t = replanned[i].candidates[plan2->chosen[i]];
        u.length_after_replan_km = u.flown_km + t.length_km;
        u.replanned_nodes = t.nodes;
        run.new_threat_sum += t.threat_cost;
      }
    }
    out.runs.push_back(std::move(run));
    if (progress) progress(r + 1, options.runs);
  }
  return out;
}

}  // namespace pheromesh::core
