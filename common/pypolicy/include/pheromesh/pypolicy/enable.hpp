// What a program calls at start to run Python policies (pypolicy.hpp), without
// pybind11's headers. A program linked by pheromesh_link_python_policies
// (cmake/Python.cmake) has PHEROMESH_WITH_PYTHON defined:
//
//   #ifdef PHEROMESH_WITH_PYTHON
//   #include "pheromesh/pypolicy/enable.hpp"
//   #endif
//   ...
//   #ifdef PHEROMESH_WITH_PYTHON
//     pheromesh::pypolicy::enable_python_policies();
//   #endif
#pragma once

namespace pheromesh::pypolicy {

// Registers the hook that reads `policy { python { ... } }`
// (core::set_python_policy_hook). Call once at start, before loading a
// scenario; idempotent. The interpreter starts later, with the first
// scenario that names a Python policy.
void enable_python_policies();

}  // namespace pheromesh::pypolicy
