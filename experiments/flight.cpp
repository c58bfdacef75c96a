#include "flight.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "launch/child_spawn.hpp"
#include "pheromesh/core/atomic_file.hpp"

namespace pheromesh::cli::experiments {

namespace {

DistributedOptions g_options;
std::vector<DistributedCheck> g_checks;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream o;
  o << f.rdbuf();
  return o.str();
}

template <class T>
std::string list(const std::vector<T>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : " ") + std::to_string(x);
  return "[" + s + "]";
}

// The fields of the config the processes rebuild from the text, compared
// with the experiment's config: what differs was changed in memory only.
std::string changed_in_memory(const core::ScenarioConfig& mem, const core::ScenarioConfig& text) {
  std::string d;
  auto cmp = [&](const char* what, auto a, auto b) {
    if (a != b) d += std::string(d.empty() ? "" : ", ") + what + " " + std::to_string(a) + " vs " + std::to_string(b);
  };
  cmp("uavs", mem.uavs, text.uavs);
  cmp("ticks", mem.ticks, text.ticks);
  cmp("width", mem.width, text.width);
  cmp("height", mem.height, text.height);
  cmp("targets", mem.targets.size(), text.targets.size());
  cmp("obstacles", mem.obstacles.size(), text.obstacles.size());
  if (mem.policy != text.policy) {
    d += std::string(d.empty() ? "" : ", ") + "policy " + mem.policy + " vs " + text.policy;
  }
  cmp("aco.alpha", mem.aco.alpha, text.aco.alpha);
  cmp("aco.beta", mem.aco.beta, text.aco.beta);
  cmp("aco.sensor_radius", mem.aco.sensor_radius, text.aco.sensor_radius);
  return d;
}

std::string label_of(const core::ScenarioConfig& s) { return s.name + " seed " + std::to_string(s.seed); }

void check_on_processes(const core::ScenarioConfig& s, const RunNumbers& sim, double sim_seconds) {
  DistributedCheck c;
  c.label = label_of(s);
  c.seed = s.seed;
  c.sim_seconds = sim_seconds;
  const auto t0 = Clock::now();
  auto fail = [&](std::string why) {
    c.differences = std::move(why);
    c.process_seconds = seconds_since(t0);
    g_checks.push_back(std::move(c));
  };
  if (s.source_text.empty()) return fail("the scenario was built in memory: no text to give the processes");
  auto text_config = core::patch_scenario(s, "run { seed: " + std::to_string(s.seed) + " }", s.name);
  if (!text_config) return fail(text_config.error().message);
  if (auto d = changed_in_memory(s, text_config.value()); !d.empty()) {
    return fail("the experiment changed the scenario in memory, not in its text (" + d + ")");
  }
  namespace fs = std::filesystem;
  char dir_name[32];
  std::snprintf(dir_name, sizeof dir_name, "run-%03zu", g_checks.size() + 1);
  const fs::path dir = fs::path(g_options.work_dir) / dir_name;
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir, ec);
  if (ec) return fail("cannot create " + dir.string() + ": " + ec.message());
  c.run_dir = dir.string();
  const std::string scenario = (dir / "scenario.textproto").string();
  if (auto w = core::write_file_atomically(scenario, text_config->source_text); !w) return fail(w.error().message);
  const std::string program = g_options.program.empty() ? fs::read_symlink("/proc/self/exe", ec).string() : g_options.program;
  if (program.ends_with(" (deleted)")) {
    return fail("this pheromesh binary was replaced while the experiment ran (rebuilt?): " + program);
  }
  std::vector<std::string> args{program,   "run",   scenario,           "--clock", "lockstep",
                                "--out",   (dir / "out").string(),      "--dds",   g_options.dds,
                                "--no-record", "--progress", "10"};
  if (g_options.domain != 0) {
    args.emplace_back("--domain");
    args.push_back(std::to_string(g_options.domain));
  }
  // Bounded: a lockstep run that stalls is a failed check, not a hung experiment.
  const double timeout_s = 120.0 + 0.2 * s.ticks * (1.0 + s.uavs / 10.0);
  bool timed_out = false;
  const int status = run_bounded(args, (dir / "run.log").string(), timeout_s, timed_out);
  c.process_seconds = seconds_since(t0);
  if (timed_out) return fail("the process run did not end within " + std::to_string(static_cast<int>(timeout_s)) + " s (" + dir.string() + "/run.log)");
  if (status != 0) return fail("pheromesh run exited with " + std::to_string(status) + " (" + dir.string() + "/run.log)");
  RunNumbers proc;
  std::string error;
  if (!numbers_from_metrics_json(slurp((dir / "out" / "metrics.json").string()), proc, error)) return fail(error);
  c.differences = differences(sim, proc);
  c.equal = c.differences.empty();
  c.process_seconds = seconds_since(t0);
  g_checks.push_back(std::move(c));
}

}  // namespace

RunNumbers numbers_of(const core::RunRecorder& r) {
  RunNumbers n;
  n.ticks = r.max_tick();
  n.coverage = r.coverage().coverage();
  n.covered_cells = r.coverage().covered_cells();
  n.targets_found = static_cast<uint32_t>(r.acquisitions().found());
  n.acquisition_ticks = r.acquisitions().acquisition_ticks();
  n.revisit_response_ticks = r.revisit_response_ticks();
  n.leader_arrival_tick = r.leader_arrival_tick();
  n.deposits_sent = r.deposits_sent();
  n.field = r.field_summary();
  return n;
}

bool numbers_from_metrics_json(const std::string& text, RunNumbers& out, std::string& error) {
  const auto j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    error = "metrics.json is missing or not JSON";
    return false;
  }
  // leader_arrival_tick is left out of a run without one (docs/outputs.md).
  for (const char* key : {"ticks", "coverage", "covered_cells", "targets_found", "acquisition_ticks",
                          "revisit_response_ticks", "deposits_sent", "field"}) {
    if (!j.contains(key)) {
      error = std::string("metrics.json has no '") + key + "'";
      return false;
    }
  }
  try {
    out.ticks = j["ticks"].get<uint32_t>();
    out.coverage = j["coverage"].get<double>();
    out.covered_cells = j["covered_cells"].get<uint64_t>();
    out.targets_found = j["targets_found"].get<uint32_t>();
    out.acquisition_ticks = j["acquisition_ticks"].get<std::vector<uint32_t>>();
    out.revisit_response_ticks = j["revisit_response_ticks"].get<std::vector<uint32_t>>();
    out.leader_arrival_tick.reset();
    if (j.contains("leader_arrival_tick") && !j["leader_arrival_tick"].is_null()) {
      out.leader_arrival_tick = j["leader_arrival_tick"].get<uint32_t>();
    }
    out.deposits_sent = j["deposits_sent"].get<uint64_t>();
    out.field.clear();
    for (const auto& [k, v] : j["field"].items()) {
      if (v.is_number()) out.field[k] = v.get<double>();
    }
  } catch (const nlohmann::json::exception& e) {
    error = std::string("metrics.json: ") + e.what();
    return false;
  }
  return true;
}

std::string differences(const RunNumbers& a, const RunNumbers& b) {
  std::string d;
  auto add = [&](const std::string& what, const std::string& x, const std::string& y) {
    if (x != y) d += what + ": " + x + " (simulator) vs " + y + " (processes)\n";
  };
  // Doubles: metrics.json prints them with 17 significant digits, so an
  // equal double reads back equal; a relative 1e-12 absorbs nothing else.
  auto close = [](double x, double y) { return x == y || std::fabs(x - y) <= 1e-12 * std::max(std::fabs(x), std::fabs(y)); };
  add("ticks", std::to_string(a.ticks), std::to_string(b.ticks));
  if (!close(a.coverage, b.coverage)) add("coverage", std::to_string(a.coverage), std::to_string(b.coverage));
  add("covered_cells", std::to_string(a.covered_cells), std::to_string(b.covered_cells));
  add("targets_found", std::to_string(a.targets_found), std::to_string(b.targets_found));
  add("acquisition_ticks", list(a.acquisition_ticks), list(b.acquisition_ticks));
  add("revisit_response_ticks", list(a.revisit_response_ticks), list(b.revisit_response_ticks));
  add("leader_arrival_tick", a.leader_arrival_tick ? std::to_string(*a.leader_arrival_tick) : "none",
      b.leader_arrival_tick ? std::to_string(*b.leader_arrival_tick) : "none");
  add("deposits_sent", std::to_string(a.deposits_sent), std::to_string(b.deposits_sent));
  for (const auto& [k, v] : a.field) {
    auto it = b.field.find(k);
    if (it == b.field.end()) {
      if (std::isnan(v)) continue;  // metrics.json writes NaN as null
      add("field." + k, std::to_string(v), "missing");
    } else if (!close(v, it->second) && !(std::isnan(v) && std::isnan(it->second))) {
      char x[64], y[64];
      std::snprintf(x, sizeof x, "%.17g", v);
      std::snprintf(y, sizeof y, "%.17g", it->second);
      add("field." + k, x, y);
    }
  }
  for (const auto& [k, v] : b.field) {
    if (!a.field.contains(k)) add("field." + k, "missing", std::to_string(v));
  }
  return d;
}

void set_distributed(const DistributedOptions& o) {
  g_options = o;
  g_checks.clear();
}

const DistributedOptions& distributed_options() { return g_options; }

const std::vector<DistributedCheck>& distributed_checks() { return g_checks; }

RunNumbers fly(const core::ScenarioConfig& s, const std::function<void(const core::Simulator&, uint32_t)>& on_tick,
               bool check) {
  const auto t0 = Clock::now();
  core::Simulator sim(s);
  if (on_tick) {
    sim.run([&](uint32_t k) { on_tick(sim, k); });
  } else {
    sim.run();
  }
  RunNumbers n = numbers_of(sim.recorder());
  const double sim_seconds = seconds_since(t0);
  if (g_options.enabled && check) check_on_processes(s, n, sim_seconds);
  return n;
}

}  // namespace pheromesh::cli::experiments
