// Policies written in Python (docs/python.md, "Python policies").
//
// A scenario names a class of a Python module:
//
//   policy { python { module: "my_policy" class: "MyPolicy"
//                     config { key: "mark" number: 10 } } }
//
// The class subclasses pheromesh.UavPolicy; pheromesh makes one instance per
// UAV, `MyPolicy(config, uav)`, and calls `step(view, actions)` every tick.
// The place agents keep the layers the class declares (its `traits`) with
// pheromesh's declared layers (core/declared_layers.hpp), or with the class's
// `place_model`, a subclass of pheromesh.PlaceModel.
//
// A program that may run such a policy links this library and calls
// enable_python_policies() at start; the core itself never links Python
// (core/python_policy.hpp). The interpreter starts when the first scenario
// naming a Python policy is loaded, not before; inside a Python process (the
// `pheromesh` extension module driven from a notebook) the running
// interpreter is used.
#pragma once

#include <pybind11/pybind11.h>

#include "pheromesh/pypolicy/enable.hpp"

namespace pheromesh::pypolicy {

// The name of the module built into the interpreter this library starts (a
// built-in module, added with PyImport_AppendInittab before Py_Initialize,
// as PYBIND11_EMBEDDED_MODULE does): it holds what bind_policy_types
// registers. A policy imports `pheromesh`; when no package of that name can
// be imported, this module is made importable as `pheromesh` too. In a
// Python process whose extension module called bind_policy_types first, that
// module's UavPolicy is the base class instead, and no _pheromesh_embedded
// is made.
inline constexpr const char* kEmbeddedModule = "_pheromesh_embedded";

// Registers into `m` the types a Python policy sees:
//   UavPolicy  the base class of a policy (name, parameters, place_model,
//              traits(config), __init__(config, uav), step(view, actions),
//              field_summary(config, field));
//   PlaceModel the base class of a place model (__init__(config, region),
//              apply(deposit, tick), step(tick), value(layer, x, y));
//   Layer, Traits  what traits(config) returns;
//   View       what a UAV knows at the start of its tick (core::UavView);
//   Actions    what it does in its tick (core::UavActions);
//   Uav        one UAV: its id, start, the map, the world's obstacles and
//              targets, and its random stream;
//   Rng        the per-UAV random stream (core/rng.hpp);
//   UavState, Broadcast  a neighbour's state, a broadcast;
//   Deposit, Region, Field  what a place model and field_summary see;
//   step_of, rotate  the heading helpers of core/heading.hpp.
// The embedded module calls it; an extension module may call it instead (once
// per process: pybind11 registers each C++ type once). The first module it
// fills holds the policy API of the process.
void bind_policy_types(pybind11::module_& m);

}  // namespace pheromesh::pypolicy
