#include "pheromesh/report/report.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "pheromesh/core/atomic_file.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/sample_summary.hpp"
#include "pheromesh/core/tick_gaps.hpp"

namespace pheromesh::report {

nlohmann::json duration_summary(std::vector<double> ms) {
  const core::SampleSummary s = core::summarize(std::move(ms));
  if (s.n == 0) return {{"n", 0}};
  return {{"n", s.n}, {"mean", s.mean}, {"p50", s.p50}, {"p90", s.p90}, {"p99", s.p99}, {"max", s.max}};
}

namespace {

// What the parts of metrics_json read: the recorder, the run's description
// and whether processes flew it, on a realtime clock.
struct MetricsContext {
  const core::RunRecorder& r;
  const RunInfo& info;
  bool processes;
  // Realtime timekeeping (late ticks, gaps between tick starts) does not
  // apply to conducted ticks.
  bool realtime;
};

// Deposit counts and finished agents over the place agents (primaries).
struct PlaceTotals {
  uint64_t applied = 0, rejected = 0, received = 0;
  uint32_t finished = 0;
};

PlaceTotals place_totals(const core::RunRecorder& r) {
  PlaceTotals t;
  for (const auto& [region, h] : r.health()) {
    t.applied += h.deposits_applied;
    t.rejected += h.deposits_rejected;
    t.received += h.deposits_received;
    t.finished += h.finished ? 1 : 0;
  }
  return t;
}

// The run: program, scenario, runner, size, coverage and targets.
void add_run_identity(nlohmann::json& j, const MetricsContext& c) {
  const core::RunRecorder& r = c.r;
  const RunInfo& info = c.info;
  const bool processes = c.processes;
  const auto& s = r.scenario();
  const uint32_t finished_places = place_totals(r).finished;
  j["version"] = PHEROMESH_VERSION;  // of the program that wrote it (CMake project version)
  j["scenario"] = s.name;
  j["scenario_file"] = s.source_path;
  j["policy"] = s.policy;
  j["seed"] = s.seed;
  j["runner"] = processes ? "processes" : "simulator";
  if (processes) j["dds"] = info.transport;
  j["clock"] = info.clock;
  j["ticks"] = r.max_tick();
  j["uavs"] = r.uavs().size();
  j["uavs_expected"] = info.uavs_expected;
  j["place_agents"] = r.health().size();
  j["place_agents_finished"] = finished_places;
  j["coverage"] = r.coverage().coverage();
  j["reachable_cells"] = r.coverage().reachable_cells();
  j["covered_cells"] = r.coverage().covered_cells();
  j["targets_total"] = r.acquisitions().size();  // the scenario's and those added from the console
  j["targets_found"] = r.acquisitions().found();
  j["acquisition_ticks"] = r.acquisitions().acquisition_ticks();
  j["revisit_response_ticks"] = r.revisit_response_ticks();
  if (r.leader_arrival_tick()) j["leader_arrival_tick"] = *r.leader_arrival_tick();
}

// Times to get there, censored at the last tick: absent if not reached.
void add_times_to_goals(nlohmann::json& j, const core::RunRecorder& r, const std::vector<core::TickRow>& rows) {
  if (const auto t = core::first_tick_at_coverage(rows, 0.5)) j["ticks_to_coverage_50"] = *t;
  if (const auto t = core::first_tick_at_coverage(rows, 0.9)) j["ticks_to_coverage_90"] = *t;
  if (const auto t = core::all_targets_found_tick(r.acquisitions())) j["ticks_to_all_targets"] = *t;
}

void add_deposits(nlohmann::json& j, const MetricsContext& c) {
  const core::RunRecorder& r = c.r;
  const PlaceTotals totals = place_totals(r);
  j["deposits_sent"] = r.deposits_sent();
  j["deposits_received"] = totals.received;
  j["deposits_applied"] = totals.applied;
  j["deposits_rejected"] = totals.rejected;
  // No silent loss (docs/faults.md): what the UAVs sent and no place agent
  // counted, and what the UAVs themselves saw unconfirmed by their home.
  j["deposits_lost"] = r.deposits_lost();
  if (c.processes) j["deposits_unconfirmed_by_uavs"] = r.deposits_unconfirmed_by_uavs();
}

// Every place agent and replica, and what the place agents receive.
void add_place_replicas(nlohmann::json& j, const MetricsContext& c) {
  const core::RunRecorder& r = c.r;
  const RunInfo& info = c.info;
  const bool processes = c.processes;
  uint64_t duplicates = 0;
  nlohmann::json replicas = nlohmann::json::object();
  for (const auto& [id, h] : r.replica_health()) {
    duplicates += h.deposits_duplicate;
    const std::string name = "place-" + std::to_string(h.region) + (h.replica > 0 ? ".r" + std::to_string(h.replica) : "");
    nlohmann::json& p = replicas[name];
    p = {{"region", h.region},
         {"replica", h.replica},
         {"tick", h.tick},
         {"finished", h.finished},
         {"lost", r.place_departed(id) && !h.finished},
         {"deposits_received", h.deposits_received},
         {"deposits_applied", h.deposits_applied}};
    if (processes) {
      p["deposits_duplicate"] = h.deposits_duplicate;
      p["bytes_received"] = h.bytes_received;
    }
  }
  if (processes) j["deposits_duplicate_dropped"] = duplicates;
  // What a place agent receives per tick (payload bytes, core::payload_bytes),
  // the mean over the primaries: local traffic does not grow with the map.
  double place_bytes = 0.0;
  for (const auto& [region, h] : r.health()) place_bytes += static_cast<double>(h.bytes_received) / (h.tick + 1.0);
  if (processes) {
    j["place_bytes_received_per_tick"] =
        r.health().empty() ? 0.0 : place_bytes / static_cast<double>(r.health().size());
  }
  j["place_replicas"] = replicas;
  // Per conducted or flown tick (ticks + 1 of them).
  if (info.ground_bytes_received) {
    j["ground_bytes_received_per_tick"] = static_cast<double>(*info.ground_bytes_received) / (r.max_tick() + 1.0);
  }
}

void add_faults(nlohmann::json& j, const MetricsContext& c) {
  const core::RunRecorder& r = c.r;
  const bool processes = c.processes;
  if (processes) j["place_agents_alive"] = r.regions_alive();
  j["uavs_killed"] = r.uavs_killed();
  j["places_killed"] = r.places_killed();
  j["regions_frozen"] = r.regions_frozen();
  if (processes) {
    j["samples_rejected_by_ground"] = r.samples_rejected();
    j["uav_states_stale"] = r.states_stale();
    j["uav_departures_stale"] = r.departures_stale();
  }
}

// Well-formed samples refused as implausible (core/plausibility.hpp), per
// reason: in total and by who refused them.
void add_refusals(nlohmann::json& j, const core::RunRecorder& r) {
  const core::RefusalCounts by_places = r.refused_by_places(), by_uavs = r.refused_by_uavs();
  nlohmann::json refused = nlohmann::json::object();
  nlohmann::json refused_by = {{"places", nlohmann::json::object()}, {"uavs", nlohmann::json::object()},
                               {"ground", nlohmann::json::object()}};
  for (std::size_t i = 0; i < core::kRefusalCount; ++i) {
    const auto why = static_cast<core::Refusal>(i);
    const std::string name = core::refusal_name(why);
    refused[name] = uint64_t{by_places[why]} + by_uavs[why] + r.refused()[why];
    refused_by["places"][name] = by_places[why];
    refused_by["uavs"][name] = by_uavs[why];
    refused_by["ground"][name] = r.refused()[why];
  }
  j["refused"] = refused;
  j["refused_by"] = refused_by;
}

// The states each UAV's gateway refused as implausible (the same in the
// simulator and the processes: core::StateGate), for the run's summary.
void add_refused_states(nlohmann::json& j, const core::RunRecorder& r) {
  if (r.refused_states().empty()) return;
  nlohmann::json states = {
      {"max_step", r.max_step()}, {"total", r.states_refused()}, {"uavs", nlohmann::json::object()}};
  for (const auto& [uav, rs] : r.refused_states()) {
    const core::RefusedMove m = core::first_refused_move(rs);
    states["uavs"][std::to_string(uav)] = {{"count", rs.count},
                                           {"first_tick", rs.first.tick},
                                           {"moved_cells", m.cells},
                                           {"in_ticks", m.ticks},
                                           {"from", rs.from_start ? "start" : "last_accepted"}};
  }
  j["states_refused"] = states;
}

// Sums over the UAVs for the traffic figures.
struct UavTotals {
  uint64_t tile_samples = 0, uav_ticks = 0, samples = 0;
};

// Each UAV's status, and keeping time (realtime): UAV ticks flown, and those
// that started more than one tick period late, over the swarm and for the worst UAV.
UavTotals add_uav_status(nlohmann::json& j, const MetricsContext& c) {
  const core::RunRecorder& r = c.r;
  const bool processes = c.processes;
  const bool realtime = c.realtime;
  nlohmann::json per_uav = nlohmann::json::object();
  uint64_t tile_samples = 0, uav_ticks = 0, ticks_late = 0, samples = 0;
  double late_share_max = 0.0;
  for (const auto& [id, u] : r.uavs()) {
    nlohmann::json& status = per_uav[std::to_string(id)];
    status = {{"last_tick", u.last.tick},
              {"heard_tick", u.heard_tick},
              {"x", u.last.x},
              {"y", u.last.y},
              {"role", core::role_name(u.last.role)},
              {"finished", u.finished},
              {"deposits_sent", u.last.deposits_sent},
              {"tile_samples_received", u.last.tile_samples_received}};
    if (processes) status["samples_received"] = u.last.samples_received;
    if (realtime) {
      status["ticks_late"] = u.last.ticks_late;
      status["tick_gap_max_ms"] = u.last.tick_gap_max_ms;
      status["tick_gaps_over_2"] = u.last.tick_gaps_over_2;
    }
    samples += u.last.samples_received;
    tile_samples += u.last.tile_samples_received;
    uav_ticks += u.heard_tick;  // a refused state's tick was flown too
    ticks_late += u.last.ticks_late;
    if (u.last.tick > 0) late_share_max = std::max(late_share_max, static_cast<double>(u.last.ticks_late) / u.last.tick);
  }
  j["uav_status"] = per_uav;
  j["uav_ticks_flown"] = uav_ticks;
  if (realtime) {
    j["uav_ticks_late"] = ticks_late;
    j["uav_late_share"] = uav_ticks > 0 ? static_cast<double>(ticks_late) / static_cast<double>(uav_ticks) : 0.0;
    j["uav_late_share_max"] = late_share_max;
  }
  return {tile_samples, uav_ticks, samples};
}

// Survivors keep their clock (issue 14): the longest gap between two tick
// starts of a UAV / place agent that ran to the end, in tick periods, and
// the gaps longer than two periods, summed. Realtime runs only (0 in lockstep).
void add_tick_gaps(nlohmann::json& j, const MetricsContext& c) {
  const core::RunRecorder& r = c.r;
  const auto& s = r.scenario();
  uint32_t uav_gap_ms = 0, uav_gaps = 0, place_gap_ms = 0, place_gaps = 0;
  for (const auto& [id, u] : r.uavs()) {
    if (!u.finished) continue;
    uav_gap_ms = std::max(uav_gap_ms, u.last.tick_gap_max_ms);
    uav_gaps += u.last.tick_gaps_over_2;
  }
  nlohmann::json place_gap_by_region = nlohmann::json::object();
  for (const auto& [region, h] : r.health()) {
    if (!h.finished) continue;
    place_gap_ms = std::max(place_gap_ms, h.tick_gap_max_ms);
    place_gaps += h.tick_gaps_over_2;
    place_gap_by_region[std::to_string(region)] = {{"tick_gap_max_ms", h.tick_gap_max_ms},
                                                   {"tick_gaps_over_2", h.tick_gaps_over_2}};
  }
  if (!c.realtime) return;
  j["uav_tick_gap_max_ms"] = uav_gap_ms;
  j["uav_tick_gap_max_periods"] = core::gap_periods(uav_gap_ms, s.tick_rate_hz);
  j["uav_tick_gaps_over_2"] = uav_gaps;
  j["place_tick_gap_max_ms"] = place_gap_ms;
  j["place_tick_gap_max_periods"] = core::gap_periods(place_gap_ms, s.tick_rate_hz);
  j["place_tick_gaps_over_2"] = place_gaps;
  j["place_tick_gaps"] = place_gap_by_region;
}

void add_lockstep(nlohmann::json& j, const RunInfo& info) {
  if (info.discovery_s) j["discovery_s"] = *info.discovery_s;
  if (!info.uav_phase_ms.empty() || !info.place_phase_ms.empty()) {
    double conducted_ms = 0;
    for (double v : info.uav_phase_ms) conducted_ms += v;
    for (double v : info.place_phase_ms) conducted_ms += v;
    j["lockstep"] = {
        {"uav_phase_ms", duration_summary(info.uav_phase_ms)},
        {"place_phase_ms", duration_summary(info.place_phase_ms)},
        {"conducted_s", conducted_ms / 1000.0},
        {"ticks_per_s",
         conducted_ms > 0 ? 1000.0 * static_cast<double>(info.place_phase_ms.size()) / conducted_ms : 0.0}};
  }
}

// [tick, coverage] every kCoverageSeriesEvery ticks and at the last tick,
// each once: the rows of series.csv at those ticks; and the field's summary.
void add_coverage_series_and_field(nlohmann::json& j, const core::RunRecorder& r,
                                   const std::vector<core::TickRow>& rows) {
  nlohmann::json series = nlohmann::json::array();
  for (const core::TickRow& row : rows) {
    if (row.tick % kCoverageSeriesEvery == 0 || row.tick + 1 == rows.size()) series.push_back({row.tick, row.coverage});
  }
  j["coverage_series"] = series;
  nlohmann::json field = nlohmann::json::object();
  for (const auto& [k, v] : r.field_summary()) field[k] = v;
  j["field"] = field;
}

}  // namespace

nlohmann::json metrics_json(const core::RunRecorder& r, const RunInfo& info) {
  const bool processes = info.runner == Runner::Processes;
  const MetricsContext c{r, info, processes, processes && info.clock == "realtime"};
  nlohmann::json j;
  add_run_identity(j, c);
  const std::vector<core::TickRow> rows = r.tick_series();
  add_times_to_goals(j, r, rows);
  add_deposits(j, c);
  add_place_replicas(j, c);
  add_faults(j, c);
  add_refusals(j, r);
  add_refused_states(j, r);
  // The launcher owns process accounting and overwrites these two.
  j["processes_killed"] = 0;
  j["processes_crashed"] = 0;
  const UavTotals totals = add_uav_status(j, c);
  const uint64_t uav_ticks = totals.uav_ticks, tile_samples = totals.tile_samples, samples = totals.samples;
  add_tick_gaps(j, c);
  add_lockstep(j, info);
  // Neighbourhood traffic: tile samples a UAV received per tick, on average.
  j["tile_samples_per_uav_tick"] =
      uav_ticks > 0 ? static_cast<double>(tile_samples) / static_cast<double>(uav_ticks) : 0.0;
  // Every DDS sample a UAV took (its views, broadcasts, commands) per tick.
  if (processes) {
    j["samples_per_uav_tick"] = uav_ticks > 0 ? static_cast<double>(samples) / static_cast<double>(uav_ticks) : 0.0;
  }
  add_coverage_series_and_field(j, r, rows);
  return j;
}

std::vector<std::string> refused_state_lines(const nlohmann::json& m) {
  std::vector<std::string> out;
  const auto it = m.find("states_refused");
  if (it == m.end() || !it->is_object()) return out;
  const auto number = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return std::string(buf);
  };
  const double max_step = it->value("max_step", 0.0);
  const auto& uavs = it->value("uavs", nlohmann::json::object());
  constexpr std::size_t kLines = 4;
  std::size_t shown = 0;
  uint64_t rest = 0;
  for (const auto& [uav, u] : uavs.items()) {
    const uint64_t count = u.value("count", uint64_t{0});
    if (shown++ >= kLines) {
      rest += count;
      continue;
    }
    const uint32_t ticks = u.value("in_ticks", 1U);
    out.push_back("uav " + uav + "'s policy moved " + number(u.value("moved_cells", 0.0)) + " cells in " +
                  (ticks == 1 ? std::string("one tick") : std::to_string(ticks) + " ticks") + " (max_step " +
                  number(max_step) + "): " + std::to_string(count) + " state" + (count == 1 ? "" : "s") +
                  " refused, the first at tick " + std::to_string(u.value("first_tick", 0U)));
  }
  if (shown > kLines) {
    out.push_back("and " + std::to_string(shown - kLines) + " more uavs: " + std::to_string(rest) + " states refused");
  }
  out.push_back(std::to_string(it->value("total", uint64_t{0})) +
                " states refused as implausible in all: their positions count nowhere (docs/writing-a-policy.md, "
                "\"How far a UAV may fly\")");
  return out;
}

std::optional<std::string> first_refusal_line(const nlohmann::json& m) {
  const auto it = m.find("states_refused");
  if (it == m.end() || !it->is_object()) return std::nullopt;
  std::optional<std::string> line;
  uint32_t earliest = 0;
  uint32_t first_uav = 0;
  const nlohmann::json uavs = it->value("uavs", nlohmann::json::object());  // a copy: items() must not outlive it
  for (const auto& [uav, u] : uavs.items()) {
    const uint32_t tick = u.value("first_tick", 0U);
    const auto id = static_cast<uint32_t>(std::stoul(uav));
    if (line && (tick > earliest || (tick == earliest && id > first_uav))) continue;
    earliest = tick;
    first_uav = id;
    line = core::describe_refusal(id, tick, {u.value("moved_cells", 0.0), u.value("in_ticks", 1U)},
                                  u.value("from", std::string("start")) == "start", it->value("max_step", 0.0));
  }
  return line;
}

bool write_field(const std::string& path, const core::MapGeometry& geo, const std::vector<std::string>& layers,
                 const FieldReader& value) {
  // A 1024 x 1024 map makes ~30 MB of text: a crash half-way must not leave
  // a field that looks complete but stops at some row.
  auto out = core::AtomicFile::create(path);
  if (!out) return false;
  FILE* f = out->stream();
  std::fprintf(f, "# pheromesh final field %d x %d\n", geo.width(), geo.height());
  for (int l = 0; l < static_cast<int>(layers.size()); ++l) {
    std::fprintf(f, "layer %s\n", layers[static_cast<std::size_t>(l)].c_str());
    for (int32_t y = 0; y < geo.height(); ++y) {
      for (int32_t x = 0; x < geo.width(); ++x) std::fprintf(f, x == 0 ? "%.9g" : " %.9g", static_cast<double>(value(l, {x, y})));
      std::fputc('\n', f);
    }
  }
  return out->commit().ok();
}

std::string json_text(const nlohmann::json& j, int indent) {
  // Strings reach here from scenarios and DDS samples; an invalid UTF-8 byte
  // must not throw type_error 316 at the end of a run and lose the file.
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

bool write_json(const std::string& dir, const std::string& file, const nlohmann::json& j, std::string& error) {
  const std::string path = (std::filesystem::path(dir) / file).string();
  auto written = core::write_file_atomically(path, json_text(j, 2) + "\n");
  if (!written) {
    error = written.error().message;
    return false;
  }
  return true;
}

}  // namespace pheromesh::report
