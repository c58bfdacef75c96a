#include "pheromesh/console/swarm_metrics.hpp"

#include <map>

#include "pheromesh/console/prometheus.hpp"

namespace pheromesh::console {

std::string swarm_metrics_text(const ConsoleState& st, const SwarmCounters& c) {
  Exposition e;
  const auto d = [](uint64_t v) { return static_cast<double>(v); };
  std::map<std::string, int> uavs{{"alive", 0}, {"stale", 0}, {"dead", 0}, {"finished", 0}};
  for (const auto& [id, u] : st.uavs) ++uavs[to_string(u.liveness)];
  e.family("pheromesh_uavs", "gauge", "UAVs by liveness as the ground station sees them.");
  for (const auto& [k, n] : uavs) e.sample("pheromesh_uavs", {{"state", k}}, n);
  std::map<std::string, int> places{{"alive", 0}, {"stale", 0}, {"dead", 0}, {"finished", 0}};
  for (const auto& r : st.regions) ++places[to_string(r.liveness)];
  e.family("pheromesh_place_agents", "gauge", "Place agents by liveness.");
  for (const auto& [k, n] : places) e.sample("pheromesh_place_agents", {{"state", k}}, n);
  e.family("pheromesh_tick", "gauge", "Highest UAV tick seen.");
  e.sample("pheromesh_tick", st.tick);
  e.family("pheromesh_paused", "gauge", "1 while the swarm is paused from the console.");
  e.sample("pheromesh_paused", st.paused ? 1 : 0);
  e.family("pheromesh_coverage_ratio", "gauge", "Reachable cells seen at least once, 0..1.");
  e.sample("pheromesh_coverage_ratio", c.coverage);
  e.family("pheromesh_uncertainty_ratio", "gauge", "Mean environmental uncertainty over reachable cells, 0..1 (docs/console.md).");
  e.sample("pheromesh_uncertainty_ratio", c.uncertainty);
  e.family("pheromesh_targets", "gauge", "Targets by status.");
  e.sample("pheromesh_targets", {{"status", "found"}}, d(c.targets_found));
  e.sample("pheromesh_targets", {{"status", "total"}}, d(c.targets_total));
  e.family("pheromesh_deposits_sent_total", "counter", "Deposits the UAVs report having sent.");
  e.sample("pheromesh_deposits_sent_total", d(c.deposits_sent));
  e.family("pheromesh_region_deposits_applied_total", "counter", "Deposits a place agent applied to its layers.");
  for (const auto& r : st.regions) {
    e.sample("pheromesh_region_deposits_applied_total", {{"region", std::to_string(r.id)}}, d(r.deposits_applied));
  }
  e.family("pheromesh_region_deposits_rejected_total", "counter", "Deposits a place agent rejected.");
  for (const auto& r : st.regions) {
    e.sample("pheromesh_region_deposits_rejected_total", {{"region", std::to_string(r.id)}}, d(r.deposits_rejected));
  }
  e.family("pheromesh_region_tick_rate_hz", "gauge", "Measured tick rate of a place agent.");
  for (const auto& r : st.regions) e.sample("pheromesh_region_tick_rate_hz", {{"region", std::to_string(r.id)}}, r.tick_rate_hz);
  e.family("pheromesh_region_up", "gauge", "1 if the place agent is alive.");
  for (const auto& r : st.regions) {
    e.sample("pheromesh_region_up", {{"region", std::to_string(r.id)}}, r.liveness == Liveness::Alive ? 1 : 0);
  }
  e.family("pheromesh_samples_rejected_total", "counter", "Malformed samples the ground station dropped.");
  e.sample("pheromesh_samples_rejected_total", d(c.samples_rejected));
  if (!c.samples_refused.empty()) {
    e.family("pheromesh_samples_refused_total", "counter",
             "Well-formed samples refused as implausible, by who refused them and why (docs/architecture.md).");
    for (const auto& [by, reasons] : c.samples_refused) {
      for (const auto& [reason, n] : reasons) {
        e.sample("pheromesh_samples_refused_total", {{"by", by}, {"reason", reason}}, d(n));
      }
    }
  }
  e.family("pheromesh_console_frames_total", "counter", "Console frames built.");
  e.sample("pheromesh_console_frames_total", d(c.frames));
  e.family("pheromesh_console_commands_total", "counter", "Console commands by result.");
  e.sample("pheromesh_console_commands_total", {{"result", "ok"}}, d(c.commands_ok));
  e.sample("pheromesh_console_commands_total", {{"result", "refused"}}, d(c.commands_refused));
  if (c.http_requests) {
    e.family("pheromesh_console_http_requests_total", "counter", "HTTP requests served by the console.");
    e.sample("pheromesh_console_http_requests_total", d(*c.http_requests));
  }
  if (c.http_body_bytes) {
    e.family("pheromesh_console_http_body_bytes_total", "counter", "Response body bytes before compression.");
    e.sample("pheromesh_console_http_body_bytes_total", d(*c.http_body_bytes));
  }
  if (c.http_refused) {
    e.family("pheromesh_console_http_refused_total", "counter", "HTTP requests and connections the console refused, by reason.");
    for (std::size_t i = 0; i < kRefusalKinds; ++i) {
      e.sample("pheromesh_console_http_refused_total", {{"reason", refusal_name(static_cast<Refusal>(i))}}, d((*c.http_refused)[i]));
    }
  }
  if (c.http_connections) {
    e.family("pheromesh_console_http_connections", "gauge", "Open connections to the console.");
    e.sample("pheromesh_console_http_connections", d(*c.http_connections));
  }
  if (c.http_long_polls_unheld) {
    e.family("pheromesh_console_http_long_polls_unheld_total", "counter",
             "Long-polls answered at once, without waiting: their client (or all) held as many as allowed.");
    e.sample("pheromesh_console_http_long_polls_unheld_total", d(*c.http_long_polls_unheld));
  }
  if (c.recording_bytes) {
    e.family("pheromesh_recording_bytes_total", "counter", "Bytes written to the console recording.");
    e.sample("pheromesh_recording_bytes_total", d(*c.recording_bytes));
  }
  return e.text();
}

}  // namespace pheromesh::console
