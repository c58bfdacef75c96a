// `policy { python { module class config } }` (core/python_policy.hpp): the
// interpreter started on demand, the module imported, the class's
// parameters read from the scenario, an entry of the policy table per policy,
// and the UAV policy that calls the class's step.
//
// The GIL: after starting the interpreter this process lets it go, and every
// call into Python takes it (gil_scoped_acquire), from whichever thread; in a
// Python process (the extension module) the caller usually holds it already.
#include <Python.h>
#include <pybind11/embed.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "embedded.hpp"
#include "handles.hpp"
#include "pheromesh/core/declared_layers.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/python_policy.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/pypolicy/pypolicy.hpp"

namespace py = pybind11;

namespace pheromesh::pypolicy {
namespace {

using detail::ActionsHandle;
using detail::FieldHandle;
using detail::RegionHandle;
using detail::UavHandle;
using detail::ViewHandle;

// Folders searched for a policy's module after the scenario's own folder
// (':'-separated), before $PYTHONPATH.
constexpr const char* kPythonPathEnv = "PHEROMESH_PYTHONPATH";

// The text of a Python exception with its traceback, as Python prints it.
std::string describe(py::error_already_set& e) {
  try {
    // No traceback (an import's SyntaxError, once importlib dropped its own frames): None.
    const py::object trace = e.trace() ? py::reinterpret_borrow<py::object>(e.trace()) : py::none();
    py::object lines = py::module_::import("traceback").attr("format_exception")(e.type(), e.value(), trace);
    std::string out = py::str("").attr("join")(lines).cast<std::string>();
    while (!out.empty() && out.back() == '\n') out.pop_back();
    return out;
  } catch (const std::exception&) {
    return e.what();
  }
}

std::vector<std::string> split_path(const char* value) {
  std::vector<std::string> out;
  if (value == nullptr) return out;
  std::string_view v(value);
  while (!v.empty()) {
    const std::size_t colon = v.find(':');
    const std::string_view part = v.substr(0, colon);
    if (!part.empty()) out.emplace_back(part);
    if (colon == std::string_view::npos) break;
    v.remove_prefix(colon + 1);
  }
  return out;
}

constexpr const char* kLineBufferedStreams =
    "import sys\n"
    "for _s in (sys.stdout, sys.stderr):\n"
    "    try:\n"
    "        _s.reconfigure(line_buffering=True)\n"
    "    except Exception:\n"
    "        pass\n";

void flush_python_streams() {
  if (Py_IsInitialized() == 0) return;
  const PyGILState_STATE g = PyGILState_Ensure();
  PyRun_SimpleString(
      "import sys\n"
      "for _s in (sys.stdout, sys.stderr):\n"
      "    try:\n"
      "        _s.flush()\n"
      "    except Exception:\n"
      "        pass\n");
  PyGILState_Release(g);
}

// Starts the interpreter unless one runs (a Python process, or a scenario
// loaded before), and lets the GIL go so that any thread may take it.
void ensure_interpreter() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (Py_IsInitialized() != 0) return;
    PyImport_AppendInittab(kEmbeddedModule, &detail::init_embedded_module);
    // No Python signal handlers: the program's own (runtime::install_shutdown_handlers) stay.
    py::initialize_interpreter(false);
    // A policy's print() goes to the process's log a line at a time (a log
    // file would otherwise hold it in an 8 KiB buffer)...
    PyRun_SimpleString(kLineBufferedStreams);
    // ...and the interpreter lives until the process ends (policies and
    // configs hold Python objects until then): never finalized, so what is
    // still buffered is flushed at exit.
    std::atexit(flush_python_streams);
    PyEval_SaveThread();
  });
}

// The module holding the policy API: an extension module that bound it (a
// notebook's `import pheromesh`), else _pheromesh_embedded, imported (or, in
// an interpreter this library did not start, made and put in sys.modules).
py::module_ api_module() {
  if (py::handle m = detail::policy_module()) return py::reinterpret_borrow<py::module_>(m);
  py::module_ sys = py::module_::import("sys");
  if (!sys.attr("modules").contains(kEmbeddedModule)) {
    try {
      return py::module_::import(kEmbeddedModule);
    } catch (py::error_already_set& e) {
      if (!e.matches(PyExc_ImportError)) throw;
    }
    PyObject* m = detail::init_embedded_module();
    if (m == nullptr) throw py::error_already_set();
    sys.attr("modules")[kEmbeddedModule] = py::reinterpret_steal<py::object>(m);
  }
  return py::module_::import(kEmbeddedModule);
}

// Makes `import pheromesh` work in a pheromesh process without the package
// installed: the module of the policy API stands in for it.
void provide_pheromesh_module(const py::module_& api) {
  py::module_ sys = py::module_::import("sys");
  if (sys.attr("modules").contains("pheromesh")) return;
  try {
    py::module_::import("pheromesh");
  } catch (py::error_already_set& e) {
    if (!e.matches(PyExc_ImportError)) throw;
    sys.attr("modules")["pheromesh"] = api;
  }
}

// What a scenario's Python policy is: the class, its parameters with the
// scenario's values, its layers and traits. Shared by copies of the scenario.
struct PythonPolicyConfig final : core::PolicyConfig {
  std::string name;
  std::string qualified;  // "module.Class", for messages
  py::object cls;
  py::object place_cls;  // the class's place_model, or None
  py::dict config;
  std::vector<core::LayerSpec> layers;
  core::PolicyTraits traits;

  [[nodiscard]] std::string_view policy() const override { return name; }
  PythonPolicyConfig() = default;
  PythonPolicyConfig(const PythonPolicyConfig&) = delete;
  PythonPolicyConfig& operator=(const PythonPolicyConfig&) = delete;
  ~PythonPolicyConfig() override {
    py::gil_scoped_acquire gil;
    cls.release().dec_ref();
    place_cls.release().dec_ref();
    config.release().dec_ref();
  }
};

const PythonPolicyConfig& config_of(const core::ScenarioConfig& s) {
  const auto* c = dynamic_cast<const PythonPolicyConfig*>(s.policy_config.get());
  if (c == nullptr) {
    throw std::logic_error("scenario '" + s.name + "': policy '" + s.policy + "' has no Python policy config");
  }
  return *c;
}

// One UAV's policy: an instance of the class, stepped with a View and an
// Actions that point at the tick under way.
class PythonUav final : public core::UavPolicy {
 public:
  PythonUav(const core::ScenarioConfig& s, const core::MapGeometry& geo, const core::World& world, uint32_t id)
      : config_(std::static_pointer_cast<const PythonPolicyConfig>(s.policy_config)), id_(id) {
    const PythonPolicyConfig& c = *config_;
    cell_ = core::uav_start(s, c.traits, id);
    py::gil_scoped_acquire gil;
    auto uav = std::make_unique<UavHandle>();
    uav->id = id;
    uav->start = cell_;
    uav->seed = s.seed;
    uav->ticks = s.ticks;
    uav->geo = &geo;
    uav->world = &world;
    // The UAV's own stream (core/rng.hpp): the same numbers in every program.
    uav->rng = core::Rng(core::stream_seed(s.seed, "python-uav", id));
    auto view = std::make_unique<ViewHandle>();
    auto actions = std::make_unique<ActionsHandle>();
    actions->geo = &geo;
    actions->world = &world;
    actions->layers = static_cast<int>(c.layers.size());
    view_ = view.get();
    actions_ = actions.get();
    view_obj_ = py::cast(std::move(view));
    actions_obj_ = py::cast(std::move(actions));
    try {
      obj_ = c.cls(py::dict(c.config), py::cast(std::move(uav)));
      step_ = obj_.attr("step");
    } catch (py::error_already_set& e) {
      throw std::runtime_error("python policy " + c.qualified + ": uav " + std::to_string(id) +
                               ": the class's __init__ raised:\n" + describe(e));
    }
  }
  PythonUav(const PythonUav&) = delete;
  PythonUav& operator=(const PythonUav&) = delete;
  ~PythonUav() override {
    py::gil_scoped_acquire gil;
    for (py::object* o : {&step_, &obj_, &view_obj_, &actions_obj_}) o->release().dec_ref();
  }

  void step(const core::UavView& view, core::UavActions& out) override {
    py::gil_scoped_acquire gil;
    view_->view = &view;
    actions_->out = &out;
    actions_->state_set = false;
    // Valid during this step only: a policy that keeps them gets an error, not stale memory.
    struct Reset {
      ViewHandle* v;
      ActionsHandle* a;
      ~Reset() {
        v->view = nullptr;
        a->out = nullptr;
      }
    } reset{view_, actions_};
    try {
      step_(view_obj_, actions_obj_);
    } catch (py::error_already_set& e) {
      throw std::runtime_error("python policy " + config_->qualified + ": uav " + std::to_string(id_) + " tick " +
                               std::to_string(view.tick) + ": step raised:\n" + describe(e));
    }
    if (!actions_->state_set) {
      throw std::runtime_error("python policy " + config_->qualified + ": uav " + std::to_string(id_) + " tick " +
                               std::to_string(view.tick) +
                               ": step did not call actions.set_state(x, y, ...) (every step says where the UAV is)");
    }
    cell_ = {static_cast<int32_t>(std::lround(out.state.x)), static_cast<int32_t>(std::lround(out.state.y))};
  }

  [[nodiscard]] core::Cell cell() const override { return cell_; }

 private:
  std::shared_ptr<const PythonPolicyConfig> config_;
  uint32_t id_;
  core::Cell cell_{};
  py::object obj_, step_, view_obj_, actions_obj_;
  ViewHandle* view_ = nullptr;        // owned by view_obj_
  ActionsHandle* actions_ = nullptr;  // owned by actions_obj_
};

// ---------------------------------------------------------------- the entries
core::PolicyTraits entry_traits(const core::ScenarioConfig& s) { return config_of(s).traits; }

std::unique_ptr<core::UavPolicy> entry_make_uav(const core::ScenarioConfig& s, const core::MapGeometry& geo,
                                                const core::World& world, uint32_t id) {
  config_of(s);  // a clear error for a config of another kind
  return std::make_unique<PythonUav>(s, geo, world, id);
}

// One region's place model written in Python (the class's place_model): no
// halo exchange, its own region only.
class PythonPlace final : public core::PlaceModel {
 public:
  PythonPlace(const core::ScenarioConfig& s, const core::MapGeometry& geo, core::RegionId region)
      : config_(std::static_pointer_cast<const PythonPolicyConfig>(s.policy_config)), region_(region) {
    const PythonPolicyConfig& c = *config_;
    py::gil_scoped_acquire gil;
    auto r = std::make_unique<RegionHandle>();
    r->id = region;
    r->rect = geo.region_rect(region);
    r->layers = static_cast<int>(c.layers.size());
    try {
      obj_ = c.place_cls(py::dict(c.config), py::cast(std::move(r)));
      apply_ = obj_.attr("apply");
      step_ = obj_.attr("step");
      value_ = obj_.attr("value");
    } catch (py::error_already_set& e) {
      throw std::runtime_error(where() + ": the place model's __init__ raised:\n" + describe(e));
    }
  }
  PythonPlace(const PythonPlace&) = delete;
  PythonPlace& operator=(const PythonPlace&) = delete;
  ~PythonPlace() override {
    py::gil_scoped_acquire gil;
    for (py::object* o : {&apply_, &step_, &value_, &obj_}) o->release().dec_ref();
  }

  std::optional<std::string> apply(const core::DepositMsg& d, uint32_t tick,
                                   std::vector<core::TargetEventMsg>& /*events*/) override {
    py::gil_scoped_acquire gil;
    try {
      const py::object r = apply_(py::cast(d, py::return_value_policy::copy), tick);
      if (r.is_none()) return std::nullopt;
      return py::str(r).cast<std::string>();
    } catch (py::error_already_set& e) {
      throw std::runtime_error(where() + " tick " + std::to_string(tick) + ": apply raised:\n" + describe(e));
    }
  }
  core::HaloRing begin_step(uint32_t tick, std::vector<core::TargetEventMsg>& /*events*/) override {
    tick_ = tick;
    return core::HaloRing{region_, {}, {}};  // empty rings: nothing crosses a border
  }
  void accept_halo(const core::Rect& /*neighbour_rect*/, const core::HaloRing& /*ring*/) override {}
  void finish_step() override {
    py::gil_scoped_acquire gil;
    try {
      step_(tick_);
    } catch (py::error_already_set& e) {
      throw std::runtime_error(where() + " tick " + std::to_string(tick_) + ": step raised:\n" + describe(e));
    }
  }
  [[nodiscard]] float value(int layer, core::Cell c) const override {
    py::gil_scoped_acquire gil;
    try {
      return value_(layer, c.x, c.y).cast<float>();
    } catch (py::error_already_set& e) {
      throw std::runtime_error(where() + ": value raised:\n" + describe(e));
    } catch (const py::cast_error&) {
      throw std::runtime_error(where() + ": value(layer, x, y) must return a number");
    }
  }

 private:
  [[nodiscard]] std::string where() const {
    return "python place model " + config_->qualified + " (region " + std::to_string(region_) + ")";
  }
  std::shared_ptr<const PythonPolicyConfig> config_;
  core::RegionId region_;
  uint32_t tick_ = 0;
  py::object obj_, apply_, step_, value_;
};

std::unique_ptr<core::PlaceModel> entry_make_place(const core::ScenarioConfig& s, const core::MapGeometry& geo,
                                                   core::RegionId region) {
  const PythonPolicyConfig& c = config_of(s);
  bool python_place = false;
  {
    py::gil_scoped_acquire gil;
    python_place = !c.place_cls.is_none();
  }
  if (python_place) return std::make_unique<PythonPlace>(s, geo, region);
  return core::make_declared_layers_place(c.layers, geo, region);
}

// The class's field_summary(config, field): {name: number} for metrics.json "field".
std::map<std::string, double> entry_field_summary(const core::ScenarioConfig& s, const core::FieldLookup& value) {
  const PythonPolicyConfig& c = config_of(s);
  py::gil_scoped_acquire gil;
  auto field = std::make_unique<FieldHandle>();
  field->lookup = &value;
  field->width = s.width;
  field->height = s.height;
  field->layers = static_cast<int>(c.layers.size());
  FieldHandle* raw = field.get();
  py::object handle = py::cast(std::move(field));
  std::map<std::string, double> out;
  try {
    const py::object summary = c.cls.attr("field_summary")(py::dict(c.config), handle);
    raw->lookup = nullptr;
    if (!summary.is_none()) {
      for (const auto& [k, v] : py::dict(summary)) out[py::str(k).cast<std::string>()] = v.cast<double>();
    }
  } catch (py::error_already_set& e) {
    raw->lookup = nullptr;
    throw std::runtime_error("python policy " + c.qualified + ": field_summary raised:\n" + describe(e));
  } catch (const py::cast_error& e) {
    raw->lookup = nullptr;
    throw std::runtime_error("python policy " + c.qualified +
                             ": field_summary must return a dict {name: number}: " + std::string(e.what()));
  }
  return out;
}

// The Python policies this process loaded, by name; the class each name is of.
struct Registered {
  py::object cls;
  core::PolicyEntry entry{};
};
std::mutex g_mutex;
std::map<std::string, Registered, std::less<>>& registry() {
  static auto* r = new std::map<std::string, Registered, std::less<>>();  // never destroyed: holds Python objects
  return *r;
}

const core::PolicyEntry* find_entry(std::string_view name) {
  std::lock_guard lock(g_mutex);
  const auto it = registry().find(name);
  return it == registry().end() ? nullptr : &it->second.entry;
}

// The kind of a parameter, from its default's type.
enum class Kind { Number, Integer, Text, Flag };

std::optional<Kind> kind_of(const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return Kind::Flag;  // before int: bool is an int in Python
  if (py::isinstance<py::int_>(v)) return Kind::Integer;
  if (py::isinstance<py::float_>(v)) return Kind::Number;
  if (py::isinstance<py::str>(v)) return Kind::Text;
  return std::nullopt;
}

using Errors = std::vector<core::PythonPolicyError>;

// sys.path: the scenario's folder, then $PHEROMESH_PYTHONPATH, before the rest
// (which holds $PYTHONPATH). Returns the folders in the order searched, for messages.
std::vector<std::string> set_search_path(const std::string& scenario_dir) {
  std::vector<std::string> first;
  if (!scenario_dir.empty()) first.push_back(scenario_dir);
  for (auto& p : split_path(std::getenv(kPythonPathEnv))) first.push_back(std::move(p));
  py::list path = py::module_::import("sys").attr("path");
  for (auto it = first.rbegin(); it != first.rend(); ++it) {
    const py::str entry(*it);
    while (path.contains(entry)) path.attr("remove")(entry);
    path.insert(0, entry);
  }
  std::vector<std::string> searched = first;
  for (auto& p : split_path(std::getenv("PYTHONPATH"))) searched.push_back(std::move(p));
  return searched;
}

// The file a module was imported from ("(no file)" for a namespace package).
std::string file_of(const py::module_& module) {
  const py::object f = py::getattr(module, "__file__", py::none());
  return f.is_none() ? std::string("(no file)") : py::str(f).cast<std::string>();
}

std::string joined(const std::vector<std::string>& v) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : ", ") + s;
  return out.empty() ? std::string("(none)") : out;
}

// Imports the block's module into `module` and finds its class `cls`, a
// subclass of pheromesh.UavPolicy; the errors, none if it did.
Errors import_class(const core::PythonPolicyBlock& block, const py::module_& api, py::module_& module,
                    py::object& cls) {
  const std::string qualified = block.module + "." + block.class_name;
  const std::vector<std::string> searched = set_search_path(block.scenario_dir);
  try {
    module = py::module_::import(block.module.c_str());
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_ModuleNotFoundError)) {
      const std::string missing = py::str(e.value().attr("name")).cast<std::string>();
      if (block.module == missing || block.module.rfind(missing + ".", 0) == 0) {
        return {{"module", "no Python module \"" + block.module + "\" in " + joined(searched) +
                               " (the scenario's folder, $" + kPythonPathEnv + ", $PYTHONPATH) or Python's own path"}};
      }
    }
    return {{"module", "importing \"" + block.module + "\" raised:\n" + describe(e)}};
  }
  if (!py::hasattr(module, block.class_name.c_str())) {
    return {{"class", "the module \"" + block.module + "\" (" + file_of(module) +
                          ") has no class \"" + block.class_name + "\""}};
  }
  cls = module.attr(block.class_name.c_str());
  const py::object base = api.attr("UavPolicy");
  if (!py::isinstance<py::type>(cls) || PyObject_IsSubclass(cls.ptr(), base.ptr()) != 1) {
    PyErr_Clear();
    return {{"class", "\"" + qualified + "\" is not a subclass of pheromesh.UavPolicy"}};
  }
  return {};
}

// The policy's name (its class's `name`, else the class's), unique among the
// policies of this process; the errors, none if it is.
Errors policy_name(const py::object& cls, const core::PythonPolicyBlock& block, const std::string& qualified,
                   std::string& name) {
  name = block.class_name;
  if (py::object n = cls.attr("name"); !n.is_none()) {
    if (!py::isinstance<py::str>(n) || py::str(n).cast<std::string>().empty()) {
      return {{"class", qualified + ".name must be a non-empty str (or None: the class's name)"}};
    }
    name = n.cast<std::string>();
  }
  bool registered = false;
  bool other_class = false;
  {
    std::lock_guard lock(g_mutex);
    const auto it = registry().find(name);
    registered = it != registry().end();
    other_class = registered && !it->second.cls.is(cls);
  }
  if (other_class) {
    return {{"class", "the policy name \"" + name + "\" of " + qualified +
                          " is taken by another Python class this program loaded"}};
  }
  if (!registered && core::find_policy(name) != nullptr) {  // (find_policy asks find_entry: not under the lock)
    return {{"class", "the policy name \"" + name + "\" of " + qualified +
                          " is a built-in policy's or a plugin's; set the class's `name`"}};
  }
  return {};
}

// The parameters into c->config: the class's defaults, replaced by the
// scenario's values. The errors of the class; a value of the scenario that
// does not fit goes to `config` (params_ok false).
Errors read_parameters(const py::object& cls, const std::string& qualified, core::PluginConfig& config,
                       PythonPolicyConfig& c, bool& params_ok) {
  py::object params = cls.attr("parameters");
  if (!py::isinstance<py::dict>(params)) return {{"class", qualified + ".parameters must be a dict {key: default}"}};
  params_ok = true;
  for (const auto& [k, dflt] : py::dict(params)) {
    if (!py::isinstance<py::str>(k)) return {{"class", qualified + ".parameters: every key must be a str"}};
    const std::string key = py::str(k).cast<std::string>();
    const auto kind = kind_of(dflt);
    if (!kind) {
      return {{"class", qualified + ".parameters[\"" + key + "\"]: the default must be a float, int, str or bool"}};
    }
    py::object value = py::reinterpret_borrow<py::object>(dflt);
    switch (*kind) {
      case Kind::Number:
        if (const auto v = config.number(key)) value = py::float_(*v);
        break;
      case Kind::Integer:
        if (const auto v = config.number(key)) {
          if (*v != std::floor(*v) || std::abs(*v) > 9.0e15) {
            config.fail(key, "must be a whole number (the policy's default is an int)");
            params_ok = false;
          } else {
            value = py::int_(static_cast<long long>(*v));
          }
        }
        break;
      case Kind::Text:
        if (const auto v = config.text(key)) value = py::str(*v);
        break;
      case Kind::Flag:
        if (const auto v = config.flag(key)) value = py::bool_(*v);
        break;
    }
    c.config[k] = value;
  }
  return {};
}

// The traits and layers from the parameters (cls.traits(config)), checked; the errors, none if they fit.
Errors read_traits(const py::object& cls, const std::string& qualified, PythonPolicyConfig& c) {
  py::object traits;
  try {
    traits = cls.attr("traits")(py::dict(c.config));
  } catch (py::error_already_set& e) {
    return {{"class", qualified + ".traits(config) raised:\n" + describe(e)}};
  }
  try {
    for (const py::handle l : traits.attr("layers")) {
      core::LayerSpec spec;
      spec.name = py::str(l.attr("name")).cast<std::string>();
      spec.evaporation = l.attr("evaporation").cast<double>();
      spec.diffusion = l.attr("diffusion").cast<double>();
      spec.max = static_cast<float>(l.attr("max").cast<double>());
      c.layers.push_back(std::move(spec));
    }
    c.traits.sensor_radius = traits.attr("sensor_radius").cast<double>();
    c.traits.view_radius = traits.attr("view_radius").cast<double>();
    c.traits.max_step = traits.attr("max_step").cast<double>();
    // Absent on a Traits-like object of an older script: it reads them.
    c.traits.reads_neighbours = py::getattr(traits, "reads_neighbours", py::bool_(true)).cast<bool>();
  } catch (const std::exception& e) {
    return {{"class", qualified + ".traits(config) must return a pheromesh.Traits of pheromesh.Layer: " +
                          std::string(e.what())}};
  }
  if (c.layers.empty()) return {{"class", qualified + ".traits(config) declares no layer"}};
  if (auto ok = core::check_layer_specs(c.layers); !ok) {
    return {{"class", qualified + ".traits(config): " + ok.error().message}};
  }
  for (const auto& [what, v, lo, hi] : {std::tuple{"sensor_radius", c.traits.sensor_radius, 0.0, 64.0},
                                        std::tuple{"view_radius", c.traits.view_radius, 0.0, 64.0},
                                        std::tuple{"max_step", c.traits.max_step, 0.0, 64.0}}) {
    if (!(v > lo && v <= hi)) {
      return {{"class", qualified + ".traits(config): " + what + " must be in (0, 64] (got " + std::to_string(v) +
                            ")"}};
    }
  }
  core::declare_layers(c.traits, c.layers);
  return {};
}

// The class's place model (None, or a subclass of pheromesh.PlaceModel); the errors, none if it fits.
Errors read_place_model(const py::object& cls, const py::module_& api, const std::string& qualified,
                        PythonPolicyConfig& c) {
  c.place_cls = py::getattr(cls, "place_model", py::none());
  if (!c.place_cls.is_none() && (!py::isinstance<py::type>(c.place_cls) ||
                                 PyObject_IsSubclass(c.place_cls.ptr(), api.attr("PlaceModel").ptr()) != 1)) {
    PyErr_Clear();
    return {{"class", qualified + ".place_model must be a subclass of pheromesh.PlaceModel (or None)"}};
  }
  return {};
}

// `name` in this process's registry of Python policies, once.
void register_policy(const std::string& name, const py::object& cls, bool broadcasts) {
  std::lock_guard lock(g_mutex);
  auto [it, added] = registry().try_emplace(name);
  if (!added) return;
  it->second.cls = cls;
  it->second.entry = core::PolicyEntry{
      .name = it->first,
      .parse = nullptr,
      .parse_scenario_fields = nullptr,
      .traits = &entry_traits,
      .broadcasts = broadcasts,
      .make_uav = &entry_make_uav,
      .make_place = &entry_make_place,
      .field_summary = &entry_field_summary,
  };
}

Errors build(const core::PythonPolicyBlock& block, core::PluginConfig& config, core::ScenarioConfig& cfg) {
  ensure_interpreter();
  py::gil_scoped_acquire gil;
  const std::string qualified = block.module + "." + block.class_name;
  const py::module_ api = api_module();
  provide_pheromesh_module(api);
  py::module_ module;
  py::object cls;
  if (auto e = import_class(block, api, module, cls); !e.empty()) return e;
  std::string name;
  if (auto e = policy_name(cls, block, qualified, name); !e.empty()) return e;
  auto c = std::make_shared<PythonPolicyConfig>();
  c->name = name;
  c->qualified = qualified;
  c->cls = cls;
  bool params_ok = true;
  if (auto e = read_parameters(cls, qualified, config, *c, params_ok); !e.empty()) return e;
  cfg.policy = name;  // for the errors of unread keys, which the parser adds
  if (!params_ok) return {};
  if (auto e = read_traits(cls, qualified, *c); !e.empty()) return e;
  if (auto e = read_place_model(cls, api, qualified, *c); !e.empty()) return e;
  const bool broadcasts = py::hasattr(cls, "broadcasts") && py::bool_(cls.attr("broadcasts"));
  register_policy(name, cls, broadcasts);
  cfg.policy = name;
  cfg.python = core::ScenarioConfig::PythonSource{block.module, block.class_name,
                                                  file_of(module)};
  cfg.policy_config = std::shared_ptr<const core::PolicyConfig>(std::move(c));
  return {};
}

const core::PythonPolicyHook kHook{.build = &build, .find = &find_entry};

}  // namespace

void enable_python_policies() { core::set_python_policy_hook(&kHook); }

}  // namespace pheromesh::pypolicy
