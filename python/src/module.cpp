// pheromesh._pheromesh: the C++ side of `import pheromesh` (docs/python.md).
// Thin: it loads scenarios with the core (overrides and all, exactly as
// `pheromesh --set` does), runs core::Simulator and hands the numbers to
// Python as NumPy arrays over buffers it gives away (no copy), writes the
// same OUT files as `pheromesh sim` through the front door, and knows where
// this build or installation keeps the shipped scenarios and the `pheromesh`
// program. The typed, documented API is python/pheromesh/*.py.
//
// The core and the scenario schema's generated code are linked statically
// into this module and nowhere else in a Python process: a process may hold
// only one copy of the schema (docs/writing-a-policy.md). Inside a pheromesh
// process that embeds an interpreter the package does not load this module
// at all (python/pheromesh/__init__.py).
#include <dlfcn.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "pheromesh/core/faults.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/frontdoor/metric_scalars.hpp"
#include "pheromesh/frontdoor/scenario_paths.hpp"
#include "pheromesh/frontdoor/sim_outputs.hpp"
#include "pheromesh/frontdoor/sim_recording.hpp"
#include "pheromesh/report/report.hpp"

#include "pheromesh/pypolicy/enable.hpp"
#include "pheromesh/pypolicy/pypolicy.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace pheromesh::python {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A scenario the core refused: the message names file, line and field
// (python/pheromesh/_errors.py parses it into pheromesh.ScenarioError).
struct ScenarioFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The folder this module was loaded from (the package folder).
fs::path module_dir() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&module_dir), &info) == 0 || info.dli_fname == nullptr) return {};
  std::error_code ec;
  const fs::path self = fs::canonical(info.dli_fname, ec);
  return ec ? fs::path() : self.parent_path();
}

// Where the shipped scenarios are for this module: installed, relative to the
// package folder; in the build tree, also the source tree's scenarios/
// (python/CMakeLists.txt sets the paths).
// A wheel (python/make_wheel.py) carries them in the package folder.
std::vector<fs::path> scenario_dirs() {
  std::vector<fs::path> dirs;
  if (const fs::path dir = module_dir(); !dir.empty()) dirs.push_back(dir / "scenarios");
  for (auto& d : frontdoor::scenario_dirs(frontdoor::ScenarioSearch{module_dir(), PHEROMESH_PY_INSTALLED_SCENARIOS_REL,
                                                                    PHEROMESH_PY_BUILD_PACKAGE_DIR,
                                                                    PHEROMESH_SOURCE_SCENARIOS_DIR})) {
    dirs.push_back(std::move(d));
  }
  return dirs;
}

// The `pheromesh` program beside this package: installed, relative to the
// package folder; in the build tree, the build's bin/.
// A wheel carries no programs: installed from this build tree's wheel into a
// venv, the package has none beside it and takes this build's.
std::string program_path() {
  const fs::path dir = module_dir();
  std::error_code ec;
  const fs::path build_program = fs::path(PHEROMESH_BUILD_BIN_DIR) / "pheromesh";
  if (!dir.empty() && fs::equivalent(dir, PHEROMESH_PY_BUILD_PACKAGE_DIR, ec)) return build_program.string();
  const fs::path installed = (dir / PHEROMESH_PY_INSTALLED_BIN_REL / "pheromesh").lexically_normal();
  if (!fs::exists(installed, ec) && fs::exists(build_program, ec)) return build_program.string();
  return installed.string();
}

std::string resolve(const std::string& arg) {
  auto r = frontdoor::resolve_scenario(arg, scenario_dirs());
  if (!r) throw ScenarioFailure(r.error().message);
  return std::move(r).value();
}

std::vector<std::string> shipped_scenarios() { return frontdoor::shipped_scenario_names(scenario_dirs()); }

// (path, value, source) triples, in the order given: core::ScenarioOverride.
using OverrideTuple = std::tuple<std::string, std::string, std::string>;

core::ScenarioConfig load(const std::string& path, const std::vector<OverrideTuple>& overrides) {
  core::ScenarioOverrides os;
  os.reserve(overrides.size());
  for (const auto& [p, v, source] : overrides) os.push_back({p, v, source});
  auto r = core::load_scenario(path, os);
  if (!r) throw ScenarioFailure(r.error().message);
  return std::move(r).value();
}

// A NumPy array that owns `v` (moved to the heap; freed with the array).
template <class T>
py::array_t<T> give_away(std::vector<T>&& v, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(v));
  py::capsule free_it(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(std::move(shape), owned->data(), free_it);
}

template <class T>
py::array_t<T> column(std::vector<T>&& v) {
  const auto n = static_cast<py::ssize_t>(v.size());
  return give_away(std::move(v), {n});
}

py::dict series_columns(const std::vector<core::TickRow>& rows) {
  std::vector<int64_t> tick, covered, found, reporting, sent, applied, rejected;
  std::vector<double> coverage;
  for (const auto& r : rows) {
    tick.push_back(r.tick);
    coverage.push_back(r.coverage);
    covered.push_back(r.covered_cells);
    found.push_back(r.targets_found);
    reporting.push_back(r.uavs_reporting);
    sent.push_back(static_cast<int64_t>(r.deposits_sent));
    applied.push_back(static_cast<int64_t>(r.deposits_applied));
    rejected.push_back(static_cast<int64_t>(r.deposits_rejected));
  }
  // The columns of series.csv, in its order (report::kSeriesHeader).
  py::dict d;
  d["tick"] = column(std::move(tick));
  d["coverage"] = column(std::move(coverage));
  d["covered_cells"] = column(std::move(covered));
  d["targets_found"] = column(std::move(found));
  d["uavs_reporting"] = column(std::move(reporting));
  d["deposits_sent"] = column(std::move(sent));
  d["deposits_applied"] = column(std::move(applied));
  d["deposits_rejected"] = column(std::move(rejected));
  return d;
}

py::dict track_columns(const std::vector<core::TrackRow>& rows) {
  std::vector<int64_t> tick, uav;
  std::vector<double> x, y;
  py::list role;
  for (const auto& r : rows) {
    tick.push_back(r.tick);
    uav.push_back(r.uav);
    x.push_back(r.x);
    y.push_back(r.y);
    role.append(core::role_name(r.role));
  }
  // The columns of tracks.csv (report::kTracksHeader); role as names.
  py::dict d;
  d["tick"] = column(std::move(tick));
  d["uav"] = column(std::move(uav));
  d["x"] = column(std::move(x));
  d["y"] = column(std::move(y));
  d["role"] = role;
  return d;
}

// Every layer of the field the place agents hold now as a (rows, cols)
// float32 array, [y, x]: gathered once from their regions into one buffer per
// layer, which the array owns. `read_only` for a look at a run still going.
py::dict field_arrays(const core::Simulator& sim, bool read_only = false) {
  const core::ScenarioConfig& s = sim.scenario();
  const auto layers = core::policy_traits(s).layers;
  py::dict d;
  for (std::size_t l = 0; l < layers.size(); ++l) {
    std::vector<float> v(static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height));
    sim.gather_layer(static_cast<int>(l), v);
    auto a = give_away(std::move(v), {s.height, s.width});
    if (read_only) a.attr("flags").attr("writeable") = false;
    d[py::str(layers[l])] = a;
  }
  return d;
}

// The layers every `every` ticks (ticks every, 2 every, ...): one
// (frames, rows, cols) buffer per layer, filled as the run goes.
class FieldFrames {
 public:
  FieldFrames(const core::Simulator& sim, uint32_t every)
      : every_(every), cells_(static_cast<std::size_t>(sim.scenario().width) * static_cast<std::size_t>(sim.scenario().height)) {
    const std::size_t frames = every == 0 ? 0 : sim.scenario().ticks / every;
    layers_.assign(static_cast<std::size_t>(sim.layer_count()), std::vector<float>(frames * cells_));
  }
  void after_tick(const core::Simulator& sim, uint32_t k) {
    if (every_ == 0 || k == 0 || k % every_ != 0) return;
    const std::size_t frame = k / every_ - 1;
    for (std::size_t l = 0; l < layers_.size(); ++l) {
      sim.gather_layer(static_cast<int>(l), std::span<float>(layers_[l]).subspan(frame * cells_, cells_));
    }
    ticks_.push_back(k);
  }
  // {layer: (frames, rows, cols)}, and the tick of every frame.
  py::tuple give_away_arrays(const core::Simulator& sim) {
    const core::ScenarioConfig& s = sim.scenario();
    const auto names = core::policy_traits(s).layers;
    const auto frames = static_cast<py::ssize_t>(ticks_.size());
    py::dict d;
    for (std::size_t l = 0; l < layers_.size(); ++l) {
      d[py::str(names[l])] = give_away(std::move(layers_[l]), {frames, s.height, s.width});
    }
    std::vector<int64_t> ticks(ticks_.begin(), ticks_.end());
    return py::make_tuple(d, column(std::move(ticks)));
  }

 private:
  uint32_t every_;
  std::size_t cells_;
  std::vector<std::vector<float>> layers_;
  std::vector<uint32_t> ticks_;
};

// A simulator for `s` with the scenario's faults and `faults` (a schedule in
// ticks, as --faults) set, and the simulator's notes on them.
std::pair<std::unique_ptr<core::Simulator>, py::list> make_simulator(const core::ScenarioConfig& s,
                                                                      const std::string& faults_text) {
  core::FaultSchedule faults = s.faults;
  if (!faults_text.empty()) {
    auto parsed = core::parse_fault_schedule(faults_text, "faults=");
    if (!parsed) throw py::value_error(parsed.error().message);
    core::merge_fault_schedules(faults, parsed.value());
  }
  auto sim = std::make_unique<core::Simulator>(s);
  py::list notes;
  if (!faults.empty()) {
    auto n = sim->set_faults(faults, s.standby);
    if (!n) throw py::value_error("faults: " + n.error().message);
    for (const auto& note : n.value()) notes.append(note);
  }
  return {std::move(sim), notes};
}

// What a finished simulation hands to Python (pheromesh.Result), and the OUT
// files of `pheromesh sim` when `out_dir` is not "".
py::dict finished_outputs(const core::Simulator& sim, double secs, const std::string& out_dir, bool tracks,
                          const py::list& notes) {
  const nlohmann::json metrics = frontdoor::sim_metrics(sim, secs);
  py::dict out;
  if (!out_dir.empty()) {
    std::string error;
    if (!report::write_json(out_dir, "metrics.json", metrics, error)) throw std::runtime_error(error);
    if (const std::string e = frontdoor::write_sim_outputs(sim, out_dir); !e.empty()) throw std::runtime_error(e);
  }
  out["metrics_json"] = metrics.dump();
  // The row of `pheromesh sweep`'s runs.csv (its metric columns).
  out["scalars"] = frontdoor::flatten_scalars(metrics);
  out["series"] = series_columns(sim.recorder().tick_series());
  out["tracks"] = tracks ? py::object(track_columns(sim.recorder().tracks())) : py::object(py::none());
  out["fields"] = field_arrays(sim);
  out["notes"] = notes;
  return out;
}

struct SimRequest {
  std::string faults;  // schedule in ticks, added to the scenario's own (as --faults)
  bool tracks = false;
  std::string record;   // console recording path, "" none
  std::string out_dir;  // OUT files as `pheromesh sim` writes them, "" none
  uint32_t fields_every = 0;  // keep the layers every this many ticks, 0 never
};

// One simulation, as `pheromesh sim` runs it (cli/sim_command.cpp); the
// GIL is released while the simulator runs, so threads run simulations in
// parallel (pheromesh.sweep).
py::dict simulate(const core::ScenarioConfig& s, const SimRequest& req) {
  auto [sim, notes] = make_simulator(s, req.faults);
  if (req.tracks) sim->keep_tracks();
  std::unique_ptr<frontdoor::SimRecording> recording;
  if (!req.record.empty()) {
    if (const auto parent = fs::path(req.record).parent_path(); !parent.empty()) {
      std::error_code ec;
      fs::create_directories(parent, ec);
      if (ec)
        throw py::value_error("record=" + req.record + ": cannot create " + parent.string() + ": " + ec.message());
    }
    auto opened = frontdoor::SimRecording::open(req.record, *sim);
    if (!opened) throw py::value_error("record=" + req.record + ": " + opened.error().message);
    recording = std::move(opened).value();
  }
  FieldFrames frames(*sim, req.fields_every);
  bool recording_failed = false;
  const auto t0 = std::chrono::steady_clock::now();
  {
    py::gil_scoped_release unlocked;
    sim->run([&](uint32_t k) {
      if (recording && !recording_failed && !recording->after_tick(k)) recording_failed = true;
      frames.after_tick(*sim, k);
    });
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  py::dict extra;
  if (recording) {
    auto closed = recording->close();
    if (recording_failed || !closed) {
      throw std::runtime_error("the recording " + req.record + " is incomplete: " +
                               (closed ? std::string("a frame could not be written") : closed.error().message));
    }
    extra["record_frames"] = recording->frames();
    extra["record_bytes"] = closed.value();
  }
  py::dict out = finished_outputs(*sim, secs, req.out_dir, req.tracks, notes);
  for (auto item : extra) out[item.first] = item.second;
  if (req.fields_every > 0) {
    py::tuple over_time = frames.give_away_arrays(*sim);
    out["fields_over_time"] = over_time[0];
    out["fields_ticks"] = over_time[1];
  }
  return out;
}

// A simulation driven a tick at a time (pheromesh.Simulation): the core's
// lifecycle (core::Simulator: advance / add_faults / finish), nothing more.
// The run finishes by itself when its last tick has run.
class Stepper {
 public:
  Stepper(const core::ScenarioConfig& s, const std::string& faults, bool tracks) : tracks_(tracks) {
    auto made = make_simulator(s, faults);
    sim_ = std::move(made.first);
    notes_ = made.second;
    if (tracks) sim_->keep_tracks();
  }

  // Runs up to n ticks (fewer when the run ends); returns how many ran.
  uint32_t advance(uint32_t n) {
    uint32_t ran = 0;
    const auto t0 = std::chrono::steady_clock::now();
    {
      py::gil_scoped_release unlocked;
      while (ran < n && sim_->advance()) ++ran;
      if (sim_->done()) sim_->finish();
    }
    secs_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return ran;
  }

  py::list add_faults(const std::string& text) {
    auto parsed = core::parse_fault_schedule(text, "fault");
    if (!parsed) throw py::value_error(parsed.error().message);
    auto added = sim_->add_faults(parsed.value());
    if (!added) throw py::value_error(added.error().message);
    py::list notes;
    for (const auto& n : added.value()) {
      notes.append(n);
      notes_.append(n);
    }
    return notes;
  }

  // The last tick run (-1 before the first).
  [[nodiscard]] int64_t tick() const { return static_cast<int64_t>(sim_->next_tick()) - 1; }
  [[nodiscard]] uint32_t last_tick() const { return sim_->scenario().ticks; }
  [[nodiscard]] bool finished() const { return sim_->finished(); }

  py::dict uavs() const {
    std::vector<int64_t> id;
    std::vector<double> x, y, vx, vy;
    std::vector<int64_t> heading;
    std::vector<bool> alive;
    py::list role;
    for (uint32_t u = 0; u < sim_->scenario().uavs; ++u) {
      const core::UavStateMsg& st = sim_->uav(u).last_state();
      // Killed before tick 0: it never flew, it has no position.
      const double none = sim_->uav_kill_tick(u) == std::optional<uint32_t>(0) ? kNaN : 0.0;
      id.push_back(u);
      x.push_back(st.x + none);
      y.push_back(st.y + none);
      vx.push_back(st.vx + none);
      vy.push_back(st.vy + none);
      heading.push_back(st.heading);
      role.append(core::role_name(st.role));
      alive.push_back(sim_->uav_alive(u));
    }
    py::dict d;
    d["uav"] = column(std::move(id));
    d["x"] = column(std::move(x));
    d["y"] = column(std::move(y));
    d["vx"] = column(std::move(vx));
    d["vy"] = column(std::move(vy));
    d["heading"] = column(std::move(heading));
    d["role"] = role;
    py::array_t<bool> a(static_cast<py::ssize_t>(alive.size()));
    for (std::size_t i = 0; i < alive.size(); ++i) a.mutable_at(static_cast<py::ssize_t>(i)) = alive[i];
    d["alive"] = a;
    return d;
  }

  py::dict targets() const {
    const auto& cells = sim_->world().targets();
    const auto& acq = sim_->recorder().acquisitions();
    std::vector<int64_t> index, x, y, found_tick;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      index.push_back(static_cast<int64_t>(i));
      x.push_back(cells[i].x);
      y.push_back(cells[i].y);
      const auto first = acq.first(i);
      found_tick.push_back(first ? static_cast<int64_t>(*first) : -1);
    }
    py::dict d;
    d["target"] = column(std::move(index));
    d["x"] = column(std::move(x));
    d["y"] = column(std::move(y));
    d["found_tick"] = column(std::move(found_tick));
    return d;
  }

  [[nodiscard]] py::dict fields() const { return field_arrays(*sim_, true); }
  [[nodiscard]] py::dict series() const { return series_columns(sim_->recorder().tick_series()); }
  [[nodiscard]] std::string metrics_json() const { return frontdoor::sim_metrics(*sim_, secs_).dump(); }
  [[nodiscard]] py::list notes() const { return notes_; }

  py::dict result(const std::string& out_dir) const {
    if (!sim_->finished()) throw py::value_error("the run has not ended");
    return finished_outputs(*sim_, secs_, out_dir, tracks_, notes_);
  }

 private:
  std::unique_ptr<core::Simulator> sim_;
  py::list notes_;
  bool tracks_;
  double secs_ = 0;
};

}  // namespace

}  // namespace pheromesh::python

PYBIND11_MODULE(_pheromesh, m) {
  using namespace pheromesh;
  using namespace pheromesh::python;
  m.doc() =
      "The C++ side of the pheromesh package (the core, linked in). Use the package: `import pheromesh` "
      "(docs/python.md).";

  py::register_exception<ScenarioFailure>(m, "ScenarioFailure", PyExc_ValueError);

  py::class_<core::ScenarioConfig>(m, "LoadedScenario",
                                   "A scenario as the core validated it (read-only; pheromesh.Scenario wraps it).")
      .def_readonly("name", &core::ScenarioConfig::name)
      .def_readonly("source_path", &core::ScenarioConfig::source_path)
      .def_readonly("text", &core::ScenarioConfig::source_text,
                    "The scenario's text, with the overrides applied when there are any.")
      .def_readonly("width", &core::ScenarioConfig::width, "[cell]")
      .def_readonly("height", &core::ScenarioConfig::height, "[cell]")
      .def_readonly("tile_size", &core::ScenarioConfig::tile_size, "[cell]")
      .def_readonly("regions_x", &core::ScenarioConfig::regions_x)
      .def_readonly("regions_y", &core::ScenarioConfig::regions_y)
      .def_readonly("uavs", &core::ScenarioConfig::uavs)
      .def_readonly("ticks", &core::ScenarioConfig::ticks)
      .def_readonly("tick_rate_hz", &core::ScenarioConfig::tick_rate_hz, "[Hz]")
      .def_readonly("seed", &core::ScenarioConfig::seed)
      .def_readonly("standby", &core::ScenarioConfig::standby)
      .def_readonly("policy", &core::ScenarioConfig::policy)
      .def_property_readonly(
          "targets",
          [](const core::ScenarioConfig& s) {
            std::vector<std::pair<int32_t, int32_t>> t;
            for (const auto& c : s.targets) t.emplace_back(c.x, c.y);
            return t;
          },
          "(x, y) of every target [cell].")
      .def_property_readonly(
          "layers", [](const core::ScenarioConfig& s) { return core::policy_traits(s).layers; },
          "The names of the policy's pheromone layers, in the order of Result.fields.")
      .def_property_readonly(
          "fault_count", [](const core::ScenarioConfig& s) { return s.faults.events.size(); },
          "The number of the scenario's own `fault:` events.");

  m.def("resolve_scenario", &resolve, py::arg("path_or_name"),
        "A file as given, or the file of a shipped scenario's name (as `pheromesh run NAME`); "
        "raises ScenarioFailure naming the shipped scenarios.");
  m.def("shipped_scenarios", &shipped_scenarios, "The names of the shipped scenarios this installation finds.");
  m.def(
      "scenario_dirs",
      [] {
        std::vector<std::string> out;
        for (const auto& d : scenario_dirs()) out.push_back(d.string());
        return out;
      },
      "The folders searched for shipped scenarios, in order.");
  m.def("program_path", &program_path, "Where the `pheromesh` program of this build or installation is.");
  m.def("load_scenario", &load, py::arg("path"), py::arg("overrides"),
        "Loads and validates a scenario file with overrides [(path, value, source)], as `pheromesh --set`; "
        "raises ScenarioFailure.");
  m.def(
      "simulate",
      [](const core::ScenarioConfig& s, const std::string& faults, bool tracks, const std::string& record,
         const std::string& out_dir, uint32_t fields_every) {
        return simulate(s, SimRequest{faults, tracks, record, out_dir, fields_every});
      },
      py::arg("scenario"), py::arg("faults") = "", py::arg("tracks") = false, py::arg("record") = "",
      py::arg("out_dir") = "", py::arg("fields_every") = 0,
      "Runs the in-process simulator; returns metrics_json, scalars, series, tracks, fields, notes, and with "
      "fields_every > 0 fields_over_time and fields_ticks (pheromesh.sim wraps it).");

  py::class_<Stepper>(m, "Stepper",
                      "core::Simulator's lifecycle a tick at a time (pheromesh.Simulation wraps it).")
      .def(py::init<const core::ScenarioConfig&, const std::string&, bool>(), py::arg("scenario"),
           py::arg("faults") = "", py::arg("tracks") = false)
      .def("advance", &Stepper::advance, py::arg("n"),
           "Runs up to n ticks (the GIL released); returns how many ran. Finishes the run after its last tick.")
      .def("add_faults", &Stepper::add_faults, py::arg("schedule"),
           "Adds fault events timed at the next tick or later (core::Simulator::add_faults); returns their "
           "notes; raises ValueError.")
      .def_property_readonly("tick", &Stepper::tick, "The last tick run (-1 before the first).")
      .def_property_readonly("last_tick", &Stepper::last_tick, "The run's last tick (run.ticks).")
      .def_property_readonly("finished", &Stepper::finished)
      .def("uavs", &Stepper::uavs)
      .def("targets", &Stepper::targets)
      .def("fields", &Stepper::fields)
      .def("series", &Stepper::series)
      .def("metrics_json", &Stepper::metrics_json)
      .def("notes", &Stepper::notes)
      .def("result", &Stepper::result, py::arg("out_dir") = "");

  // Python policies (common/pypolicy): their types (UavPolicy, PlaceModel,
  // the view, the actions) on this module, and the hook that lets this
  // process's scenario parser run `policy { python { ... } }` in sim().
  pheromesh::pypolicy::bind_policy_types(m);
  pheromesh::pypolicy::enable_python_policies();
}
