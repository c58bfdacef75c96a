// The module that holds the policy API in this process (pypolicy.cpp,
// bindings.cpp).
#pragma once

#include <pybind11/pybind11.h>

namespace pheromesh::pypolicy::detail {

// The init function of _pheromesh_embedded: a new module with
// bind_policy_types. Added to the interpreter's built-in modules when this
// library starts the interpreter (PyImport_AppendInittab before
// Py_Initialize, as PYBIND11_EMBEDDED_MODULE would, but only then: a static
// registration would also run inside a Python process that loads an
// extension module linking this library, after Py_Initialize).
PyObject* init_embedded_module();

// The first module bind_policy_types filled (the embedded module, or an
// extension module that called it); null before. Its UavPolicy is the base
// class a policy must subclass. Call with the GIL held.
pybind11::handle policy_module();
void remember_policy_module(pybind11::handle m);

}  // namespace pheromesh::pypolicy::detail
