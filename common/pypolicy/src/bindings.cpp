// The types a Python policy sees (pypolicy.hpp, bind_policy_types) and the
// module built into every program that runs Python policies.
#include <pybind11/eval.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "embedded.hpp"
#include "handles.hpp"
#include "pheromesh/core/heading.hpp"
#include "pheromesh/pypolicy/pypolicy.hpp"

namespace py = pybind11;

namespace pheromesh::pypolicy {
namespace {

using detail::ActionsHandle;
using detail::FieldHandle;
using detail::RegionHandle;
using detail::UavHandle;
using detail::ViewHandle;

const core::UavView& live(const ViewHandle& h) {
  if (h.view == nullptr) throw std::runtime_error("a View is valid only during the step it was given to");
  return *h.view;
}

ActionsHandle& live(ActionsHandle& h) {
  if (h.out == nullptr) throw std::runtime_error("an Actions is valid only during the step it was given to");
  return h;
}

core::Cell in_map(const core::MapGeometry& geo, int32_t x, int32_t y, const char* what) {
  const core::Cell c{x, y};
  if (!geo.in_map(c)) {
    throw py::value_error(std::string(what) + ": cell (" + std::to_string(x) + ", " + std::to_string(y) +
                          ") is outside the map (" + std::to_string(geo.width()) + " x " + std::to_string(geo.height()) +
                          ")");
  }
  return c;
}

// The base classes and the plain records, in Python: what a user subclasses
// and fills in needs no C++ behind it.
constexpr const char* kPythonPart = R"PY(
class Layer:
    """A pheromone layer the place agents keep for the policy.

    Every tick each cell keeps (1 - diffusion) of its value, hands diffusion
    of it to its 8 neighbours in equal parts, then loses evaporation of the
    result; a cell holds at most `max` (docs/writing-a-policy.md, declared
    layers). At most two layers diffuse.
    """

    def __init__(self, name, evaporation=0.0, diffusion=0.0, max=1e6):
        self.name = str(name)
        self.evaporation = float(evaporation)
        self.diffusion = float(diffusion)
        self.max = float(max)

    def __repr__(self):
        return (f"Layer({self.name!r}, evaporation={self.evaporation}, "
                f"diffusion={self.diffusion}, max={self.max})")


class Traits:
    """What a policy looks like from outside: its layers (index = the layer
    number a deposit names), the sensor radius of the coverage metric, the
    radius of the tiles a UAV reads, and the farthest a UAV flies in a tick
    (cells; the plausibility check refuses farther). reads_neighbours=False
    says that step() never reads view.neighbours: its views then carry
    none, which saves most of a crowded swarm's view traffic."""

    def __init__(self, layers, sensor_radius=4.0, view_radius=5.0, max_step=1.5, reads_neighbours=True):
        self.layers = list(layers)
        self.sensor_radius = float(sensor_radius)
        self.view_radius = float(view_radius)
        self.max_step = float(max_step)
        self.reads_neighbours = bool(reads_neighbours)


class UavPolicy:
    """The base class of a policy written in Python (docs/python.md).

    Class attributes:
      name        the policy's name in reports and the console (default: the
                  class's name); not the name of a built-in policy
      parameters  {key: default}: the scenario's `config { key: ... }` it
                  reads; the default's type says the kind (float or int:
                  number, str: text, bool: flag). A key not listed is an error.

    traits(config) (a classmethod) returns the Traits. pheromesh makes one
    instance per UAV, cls(config, uav), config being the parameters with the
    scenario's values, and calls step(view, actions) every tick; step must
    call actions.set_state(x, y, ...). Random numbers come from uav.rng only,
    so that every run of a seed gives the same numbers (lockstep == sim).
    """

    name = None
    parameters = {}
    # A subclass of pheromesh.PlaceModel that keeps the layers in the place
    # agents; None: pheromesh's declared layers, as traits(config) gives them.
    place_model = None

    @classmethod
    def traits(cls, config):
        raise NotImplementedError(f"{cls.__name__}.traits(config) must return a pheromesh.Traits")

    def __init__(self, config, uav):
        self.config = config
        self.uav = uav

    def step(self, view, actions):
        raise NotImplementedError(f"{type(self).__name__}.step(view, actions) is not written")

    @classmethod
    def field_summary(cls, config, field):
        """Numbers that judge a run's final field, for metrics.json "field":
        {name: number}. field.value(layer, x, y) reads it. None by default."""
        return {}


class PlaceModel:
    """What a place agent does with the deposits of its region (docs/python.md).

    pheromesh makes one instance per region, cls(config, region), and each
    tick calls apply(deposit, tick) for every deposit received, then
    step(tick); value(layer, x, y) reads a cell of the region (for the tiles
    the UAVs read and the final field). No halo exchange: a Python place
    model sees its own region only (nothing diffuses across a border).
    """

    def __init__(self, config, region):
        self.config = config
        self.region = region

    def apply(self, deposit, tick):
        """Applies one deposit; returns None, or why it was refused (a str)."""
        raise NotImplementedError(f"{type(self).__name__}.apply(deposit, tick) is not written")

    def step(self, tick):
        """The layers' update of the tick, after its deposits."""

    def value(self, layer, x, y):
        raise NotImplementedError(f"{type(self).__name__}.value(layer, x, y) is not written")
)PY";

// The random stream and what a UAV hears of the others.
void bind_basics(py::module_& m) {
  py::class_<core::Rng>(m, "Rng", "A UAV's random stream (xoshiro256**; the same numbers on every platform)")
      .def(py::init<uint64_t>(), py::arg("seed"))
      .def("next", &core::Rng::next, "The next 64 random bits")
      .def("uniform01", &core::Rng::uniform01, "A number in [0, 1)")
      .def(
          "uniform_below",
          [](core::Rng& r, uint32_t n) {
            if (n == 0) throw py::value_error("uniform_below(n) needs n > 0");
            return r.uniform_below(n);
          },
          py::arg("n"), "An integer in [0, n), unbiased");

  py::class_<core::UavStateMsg>(m, "UavState", "A UAV's state as its neighbours see it")
      .def_readonly("uav", &core::UavStateMsg::uav)
      .def_readonly("tick", &core::UavStateMsg::tick)
      .def_readonly("x", &core::UavStateMsg::x)
      .def_readonly("y", &core::UavStateMsg::y)
      .def_readonly("vx", &core::UavStateMsg::vx)
      .def_readonly("vy", &core::UavStateMsg::vy)
      .def_readonly("heading", &core::UavStateMsg::heading)
      .def_readonly("role", &core::UavStateMsg::role);

  py::class_<core::BroadcastMsg>(m, "Broadcast", "A message of one UAV to the swarm")
      .def_readonly("uav", &core::BroadcastMsg::uav)
      .def_readonly("tick", &core::BroadcastMsg::tick)
      .def_readonly("kind", &core::BroadcastMsg::kind)
      .def_readonly("values", &core::BroadcastMsg::values);
}

// What a UAV knows at the start of its tick.
void bind_view(py::module_& m) {
  py::class_<ViewHandle>(m, "View", "What a UAV knows at the start of its tick; valid during that step only")
      .def_property_readonly("tick", [](const ViewHandle& h) { return live(h).tick; })
      .def(
          "value",
          [](const ViewHandle& h, int layer, int32_t x, int32_t y) -> std::optional<float> {
            const core::UavView& v = live(h);
            if (layer < 0 || layer >= v.tiles->layers()) {
              throw py::value_error("value: layer " + std::to_string(layer) + " is not one of the policy's " +
                                    std::to_string(v.tiles->layers()) + " layers");
            }
            return v.tiles->value(layer, core::Cell{x, y});
          },
          py::arg("layer"), py::arg("x"), py::arg("y"),
          "The pheromone of `layer` at cell (x, y), or None when its tile has not arrived (or is outside the map)")
      .def_property_readonly(
          "neighbours",
          [](const ViewHandle& h) {
            const auto n = live(h).neighbours;
            return std::vector<core::UavStateMsg>(n.begin(), n.end());
          },
          "The other UAVs over this UAV's neighbourhood (their states of the tick before), by id")
      .def_property_readonly(
          "broadcasts",
          [](const ViewHandle& h) {
            const auto b = live(h).broadcasts;
            return std::vector<core::BroadcastMsg>(b.begin(), b.end());
          },
          "The broadcasts of the tick before, own included, by UAV id");
}

// What a UAV does in its tick.
void bind_actions(py::module_& m) {
  py::class_<ActionsHandle>(m, "Actions", "What a UAV does in its tick; valid during that step only")
      .def(
          "deposit",
          [](ActionsHandle& h, int layer, int32_t x, int32_t y, double amount) {
            ActionsHandle& a = live(h);
            if (layer < 0 || layer >= a.layers) {
              throw py::value_error("deposit: layer " + std::to_string(layer) + " is not one of the policy's " +
                                    std::to_string(a.layers) + " layers");
            }
            if (!std::isfinite(amount) || amount < 0.0) {
              throw py::value_error("deposit: amount must be finite and >= 0 (got " + std::to_string(amount) + ")");
            }
            a.out->deposits.push_back(core::layer_add(*a.geo, layer, in_map(*a.geo, x, y, "deposit"), amount));
          },
          py::arg("layer"), py::arg("x"), py::arg("y"), py::arg("amount"),
          "Adds `amount` of `layer` at cell (x, y) (capped at the layer's max by its place agent)")
      .def(
          "detect",
          [](ActionsHandle& h, int32_t target) {
            ActionsHandle& a = live(h);
            const auto& targets = a.world->targets();
            if (target < 0 || static_cast<std::size_t>(target) >= targets.size()) {
              throw py::value_error("detect: target " + std::to_string(target) + " is not one of the " +
                                    std::to_string(targets.size()) + " targets");
            }
            core::DetectionMsg d;
            d.target = target;
            d.cell = targets[static_cast<std::size_t>(target)];
            a.out->detections.push_back(d);
          },
          py::arg("target"), "Reports target number `target` found")
      .def(
          "set_state",
          [](ActionsHandle& h, double x, double y, double vx, double vy, int heading, int role) {
            ActionsHandle& a = live(h);
            for (const double v : {x, y, vx, vy}) {
              if (!std::isfinite(v)) throw py::value_error("set_state: position and velocity must be finite");
            }
            if (heading < 0 || heading > 7) throw py::value_error("set_state: heading must be in 0..7");
            if (role < 0 || role > 2) throw py::value_error("set_state: role must be 0 (searcher), 1 or 2");
            in_map(*a.geo, static_cast<int32_t>(std::lround(x)), static_cast<int32_t>(std::lround(y)), "set_state");
            a.out->state.x = x;
            a.out->state.y = y;
            a.out->state.vx = vx;
            a.out->state.vy = vy;
            a.out->state.heading = static_cast<uint8_t>(heading);
            a.out->state.role = static_cast<uint8_t>(role);
            a.state_set = true;
          },
          py::arg("x"), py::arg("y"), py::arg("vx") = 0.0, py::arg("vy") = 0.0, py::arg("heading") = 0,
          py::arg("role") = 0,
          "Where the UAV is at the end of its tick [cell; a cell's centre is its integer coordinates], its "
          "velocity [cell/tick], heading (0..7, 0 = east, counter-clockwise) and role (0 searcher, 1 leader, 2 "
          "follower). Every step must call it.")
      .def(
          "broadcast",
          [](ActionsHandle& h, int kind, std::vector<double> values) {
            ActionsHandle& a = live(h);
            if (kind < 0 || kind > 255) throw py::value_error("broadcast: kind must be in 0..255");
            core::BroadcastMsg b;
            b.kind = static_cast<uint8_t>(kind);
            b.values = std::move(values);
            a.out->broadcast = std::move(b);
          },
          py::arg("kind"), py::arg("values"),
          "Sends one message to the swarm this tick (the last call wins); needs broadcasts = True on the class");
}

// What a place model sees: deposits, its region, the final field.
void bind_place_types(py::module_& m) {
  py::class_<core::DepositMsg>(m, "Deposit", "A deposit a UAV sent to a place agent")
      .def_readonly("uav", &core::DepositMsg::uav)
      .def_readonly("seq", &core::DepositMsg::seq)
      .def_readonly("tick", &core::DepositMsg::tick)
      .def_readonly("kind", &core::DepositMsg::kind, "0.. (messages.hpp DepositKind); actions.deposit sends LayerAdd")
      .def_readonly("layer", &core::DepositMsg::layer)
      .def_property_readonly("x", [](const core::DepositMsg& d) { return d.cell.x; })
      .def_property_readonly("y", [](const core::DepositMsg& d) { return d.cell.y; })
      .def_readonly("amount", &core::DepositMsg::amount);

  py::class_<RegionHandle>(m, "Region", "The region of the map a place model keeps (cells x..x+w-1, y..y+h-1)")
      .def_readonly("id", &RegionHandle::id)
      .def_property_readonly("x", [](const RegionHandle& r) { return r.rect.x0; })
      .def_property_readonly("y", [](const RegionHandle& r) { return r.rect.y0; })
      .def_property_readonly("w", [](const RegionHandle& r) { return r.rect.w; })
      .def_property_readonly("h", [](const RegionHandle& r) { return r.rect.h; })
      .def_readonly("layers", &RegionHandle::layers, "How many layers the policy declares");

  py::class_<FieldHandle>(m, "Field", "A run's final field; valid during field_summary only")
      .def_readonly("width", &FieldHandle::width)
      .def_readonly("height", &FieldHandle::height)
      .def(
          "value",
          [](const FieldHandle& h, int layer, int32_t x, int32_t y) {
            if (h.lookup == nullptr) throw std::runtime_error("a Field is valid only during field_summary");
            if (layer < 0 || layer >= h.layers || x < 0 || y < 0 || x >= h.width || y >= h.height) {
              throw py::value_error("value: no layer " + std::to_string(layer) + " or cell (" + std::to_string(x) +
                                    ", " + std::to_string(y) + ") in the field");
            }
            return (*h.lookup)(layer, core::Cell{x, y});
          },
          py::arg("layer"), py::arg("x"), py::arg("y"), "The pheromone of `layer` at cell (x, y)");
}

// One UAV, and the heading helpers.
void bind_uav(py::module_& m) {
  py::class_<UavHandle>(m, "Uav", "One UAV: its id, the map, the world it senses and its random stream")
      .def_readonly("id", &UavHandle::id)
      .def_property_readonly("start", [](const UavHandle& u) { return py::make_tuple(u.start.x, u.start.y); },
                             "The cell (x, y) the UAV starts over")
      .def_readonly("seed", &UavHandle::seed, "The run's seed")
      .def_readonly("ticks", &UavHandle::ticks, "The run's length [tick]")
      .def_property_readonly("width", [](const UavHandle& u) { return u.geo->width(); })
      .def_property_readonly("height", [](const UavHandle& u) { return u.geo->height(); })
      .def_property_readonly(
          "rng", [](UavHandle& u) -> core::Rng& { return u.rng; }, py::return_value_policy::reference_internal,
          "The UAV's random stream: the policy's only source of random numbers")
      .def(
          "in_map", [](const UavHandle& u, int32_t x, int32_t y) { return u.geo->in_map(core::Cell{x, y}); },
          py::arg("x"), py::arg("y"))
      .def(
          "is_obstacle",
          [](const UavHandle& u, int32_t x, int32_t y) { return u.world->is_obstacle(core::Cell{x, y}); },
          py::arg("x"), py::arg("y"), "True for an obstacle cell (False outside the map)")
      .def(
          "sense",
          [](const UavHandle& u, int32_t x, int32_t y, double radius) {
            return u.world->sense(core::Cell{x, y}, radius).targets;
          },
          py::arg("x"), py::arg("y"), py::arg("radius"),
          "The numbers of the targets within `radius` [cell] of (x, y) (the simulated sensor)")
      .def_property_readonly(
          "targets",
          [](const UavHandle& u) {
            py::list out;
            for (const core::Cell& c : u.world->targets()) out.append(py::make_tuple(c.x, c.y));
            return out;
          },
          "The targets' cells, by number");

  m.def(
      "step_of",
      [](int heading) {
        const core::Cell c = core::step_of(static_cast<core::Heading>(((heading % 8) + 8) % 8));
        return py::make_tuple(c.x, c.y);
      },
      py::arg("heading"), "The cell step (dx, dy) of a heading (0 = east, counter-clockwise by 45 degrees)");
  m.def(
      "rotate", [](int heading, int eighths) { return static_cast<int>(core::rotate(static_cast<core::Heading>(((heading % 8) + 8) % 8), eighths)); },
      py::arg("heading"), py::arg("eighths"), "The heading turned by `eighths` x 45 degrees counter-clockwise");
}

}  // namespace

void bind_policy_types(py::module_& m) {
  m.doc() = "pheromesh's policy API: what a policy written in Python sees (docs/python.md)";

  bind_basics(m);
  bind_view(m);
  bind_actions(m);
  bind_place_types(m);
  bind_uav(m);

  py::exec(kPythonPart, m.attr("__dict__"));
  // The classes defined by exec belong to this module, not to __main__.
  for (const char* name : {"Layer", "Traits", "UavPolicy", "PlaceModel"}) m.attr(name).attr("__module__") = m.attr("__name__");
  detail::remember_policy_module(m);
}

namespace detail {

namespace {
py::handle g_policy_module;  // a strong reference, never dropped (the module lives as long as the process)
}  // namespace

py::handle policy_module() { return g_policy_module; }

void remember_policy_module(py::handle m) {
  if (!g_policy_module) g_policy_module = m.inc_ref();
}

PyObject* init_embedded_module() {
  static py::module_::module_def def;
  py::module_ m = py::module_::create_extension_module(kEmbeddedModule, nullptr, &def);
  try {
    bind_policy_types(m);
    return m.release().ptr();
  } catch (py::error_already_set& e) {
    e.restore();
    return nullptr;
  } catch (const std::exception& e) {
    PyErr_SetString(PyExc_ImportError, e.what());
    return nullptr;
  }
}

}  // namespace detail

}  // namespace pheromesh::pypolicy
