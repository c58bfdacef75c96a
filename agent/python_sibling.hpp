// pheromesh-uav without Python, and pheromesh-uav-python beside it: a
// scenario that names a Python policy makes pheromesh-uav run the same
// command line in its sibling (exec: the same process and pid, which the
// launcher and its faults keep). A UAV of a C++ policy then maps no
// libpython, whose relocated data was a quarter of a UAV process's memory
// and whose loading a sixth of its start (docs/benchmarks.md, "Python only
// where the policy is Python").
#pragma once

namespace pheromesh::agent {

// Registers the hook (core::set_python_policy_hook) that execs `sibling`,
// found beside this program, with `argv` (which must live until the process
// ends). Call once at start, before the scenario is loaded.
void run_python_policies_in(const char* sibling, char** argv);

}  // namespace pheromesh::agent
