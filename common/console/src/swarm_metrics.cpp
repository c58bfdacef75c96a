#include "pheromesh/console/swarm_metrics.hpp"

#include <map>

#include "pheromesh/console/prometheus.hpp"

namespace pheromesh::console {

namespace {

double as_double(uint64_t v) { return static_cast<double>(v); }

// UAVs and place agents by liveness.
void add_liveness(Exposition& e, const ConsoleState& st) {
  std::map<std::string, int> uavs{{"alive", 0}, {"stale", 0}, {"dead", 0}, {"finished", 0}};
  for (const auto& [id, u] : st.uavs) ++uavs[to_string(u.liveness)];
  e.family("pheromesh_uavs", "gauge", "UAVs by liveness as the ground station sees them.");
  for (const auto& [k, n] : uavs) e.sample("pheromesh_uavs", {{"state", k}}, n);
  std::map<std::string, int> places{{"alive", 0}, {"stale", 0}, {"dead", 0}, {"finished", 0}};
  for (const auto& r : st.regions) ++places[to_string(r.liveness)];
  e.family("pheromesh_place_agents", "gauge", "Place agents by liveness.");
  for (const auto& [k, n] : places) e.sample("pheromesh_place_agents", {{"state", k}}, n);
}

// Tick, pause, coverage, uncertainty, targets and deposits sent.
void add_swarm_progress(Exposition& e, const ConsoleState& st, const SwarmCounters& c) {
  e.family("pheromesh_tick", "gauge", "Highest UAV tick seen.");
  e.sample("pheromesh_tick", st.tick);
  e.family("pheromesh_paused", "gauge", "1 while the swarm is paused from the console.");
  e.sample("pheromesh_paused", st.paused ? 1 : 0);
  e.family("pheromesh_coverage_ratio", "gauge", "Reachable cells seen at least once, 0..1.");
  e.sample("pheromesh_coverage_ratio", c.coverage);
  e.family("pheromesh_uncertainty_ratio", "gauge", "Mean environmental uncertainty over reachable cells, 0..1 (docs/console.md).");
  e.sample("pheromesh_uncertainty_ratio", c.uncertainty);
  e.family("pheromesh_targets", "gauge", "Targets by status.");
  e.sample("pheromesh_targets", {{"status", "found"}}, as_double(c.targets_found));
  e.sample("pheromesh_targets", {{"status", "total"}}, as_double(c.targets_total));
  e.family("pheromesh_deposits_sent_total", "counter", "Deposits the UAVs report having sent.");
  e.sample("pheromesh_deposits_sent_total", as_double(c.deposits_sent));
}

// Each place agent's deposits, tick rate and liveness.
void add_region_gauges(Exposition& e, const ConsoleState& st) {
  e.family("pheromesh_region_deposits_applied_total", "counter", "Deposits a place agent applied to its layers.");
  for (const auto& r : st.regions) {
    e.sample("pheromesh_region_deposits_applied_total", {{"region", std::to_string(r.id)}},
             as_double(r.deposits_applied));
  }
  e.family("pheromesh_region_deposits_rejected_total", "counter", "Deposits a place agent rejected.");
  for (const auto& r : st.regions) {
    e.sample("pheromesh_region_deposits_rejected_total", {{"region", std::to_string(r.id)}},
             as_double(r.deposits_rejected));
  }
  e.family("pheromesh_region_tick_rate_hz", "gauge", "Measured tick rate of a place agent.");
  for (const auto& r : st.regions) e.sample("pheromesh_region_tick_rate_hz", {{"region", std::to_string(r.id)}}, r.tick_rate_hz);
  e.family("pheromesh_region_up", "gauge", "1 if the place agent is alive.");
  for (const auto& r : st.regions) {
    e.sample("pheromesh_region_up", {{"region", std::to_string(r.id)}}, r.liveness == Liveness::Alive ? 1 : 0);
  }
}

// Samples the ground station dropped or refused.
void add_sample_refusals(Exposition& e, const SwarmCounters& c) {
  e.family("pheromesh_samples_rejected_total", "counter", "Malformed samples the ground station dropped.");
  e.sample("pheromesh_samples_rejected_total", as_double(c.samples_rejected));
  if (!c.samples_refused.empty()) {
    e.family("pheromesh_samples_refused_total", "counter",
             "Well-formed samples refused as implausible, by who refused them and why (docs/architecture.md).");
    for (const auto& [by, reasons] : c.samples_refused) {
      for (const auto& [reason, n] : reasons) {
        e.sample("pheromesh_samples_refused_total", {{"by", by}, {"reason", reason}}, as_double(n));
      }
    }
  }
}

// The console's own counters: frames, commands, HTTP and the recording.
void add_console_counters(Exposition& e, const SwarmCounters& c) {
  e.family("pheromesh_console_frames_total", "counter", "Console frames built.");
  e.sample("pheromesh_console_frames_total", as_double(c.frames));
  e.family("pheromesh_console_commands_total", "counter", "Console commands by result.");
  e.sample("pheromesh_console_commands_total", {{"result", "ok"}}, as_double(c.commands_ok));
  e.sample("pheromesh_console_commands_total", {{"result", "refused"}}, as_double(c.commands_refused));
  if (c.http_requests) {
    e.family("pheromesh_console_http_requests_total", "counter", "HTTP requests served by the console.");
    e.sample("pheromesh_console_http_requests_total", as_double(*c.http_requests));
  }
  if (c.http_body_bytes) {
    e.family("pheromesh_console_http_body_bytes_total", "counter", "Response body bytes before compression.");
    e.sample("pheromesh_console_http_body_bytes_total", as_double(*c.http_body_bytes));
  }
  if (c.http_refused) {
    e.family("pheromesh_console_http_refused_total", "counter", "HTTP requests and connections the console refused, by reason.");
    for (std::size_t i = 0; i < kRefusalKinds; ++i) {
      e.sample("pheromesh_console_http_refused_total", {{"reason", refusal_name(static_cast<Refusal>(i))}},
               as_double((*c.http_refused)[i]));
    }
  }
  if (c.http_connections) {
    e.family("pheromesh_console_http_connections", "gauge", "Open connections to the console.");
    e.sample("pheromesh_console_http_connections", as_double(*c.http_connections));
  }
  if (c.http_long_polls_unheld) {
    e.family("pheromesh_console_http_long_polls_unheld_total", "counter",
             "Long-polls answered at once, without waiting: their client (or all) held as many as allowed.");
    e.sample("pheromesh_console_http_long_polls_unheld_total", as_double(*c.http_long_polls_unheld));
  }
  if (c.recording_bytes) {
    e.family("pheromesh_recording_bytes_total", "counter", "Bytes written to the console recording.");
    e.sample("pheromesh_recording_bytes_total", as_double(*c.recording_bytes));
  }
}

}  // namespace

std::string swarm_metrics_text(const ConsoleState& st, const SwarmCounters& c) {
  Exposition e;
  add_liveness(e, st);
  add_swarm_progress(e, st, c);
  add_region_gauges(e, st);
  add_sample_refusals(e, c);
  add_console_counters(e, c);
  return e.text();
}

}  // namespace pheromesh::console
