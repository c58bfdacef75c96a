// A policy written in Python (`policy { python { module: "..." class: "..."
// config { ... } } }`, docs/python.md): the hook through which the scenario
// parser hands such a block to the code that runs Python.
//
// The core does not link Python (a core-only or Python-less build must keep
// working): a program that can run Python policies links the library
// pheromesh_pypolicy (common/pypolicy) and, at start, registers its hook
// (pheromesh::pypolicy::enable_python_policies). Without a hook, a scenario
// naming a Python policy is refused at the `python` block: "this program was
// built without Python support".
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "pheromesh/core/policy_plugin.hpp"
#include "pheromesh/core/policy_table.hpp"
#include "pheromesh/core/scenario.hpp"

namespace pheromesh::core {

// What the scenario says, and where its file is.
struct PythonPolicyBlock {
  std::string module;        // `module:`, as `import` takes it
  std::string class_name;    // `class:`
  std::string scenario_dir;  // the scenario file's folder, absolute; "" for text without a file
};

// An error of the block for the scenario parser to report at the line of
// `field` ("module", "class"; "" for the block itself).
struct PythonPolicyError {
  std::string field;
  std::string message;
};

struct PythonPolicyHook {
  // Imports the module, finds the class, reads its parameters through
  // `config` (errors at the parameters' lines) and sets cfg.policy,
  // cfg.policy_config and cfg.python; registers the policy's entry, which
  // `find` then returns. Errors of the block are returned (none: it worked).
  std::vector<PythonPolicyError> (*build)(const PythonPolicyBlock& block, PluginConfig& config,
                                          ScenarioConfig& cfg);
  // The entry of a Python policy a scenario loaded in this process, by name; null if none.
  const PolicyEntry* (*find)(std::string_view name);
};

// Registers the hook (null: none). A program calls it once at start, before
// it loads a scenario; `hook` must live until the process ends.
void set_python_policy_hook(const PythonPolicyHook* hook);
// The hook registered, or null.
const PythonPolicyHook* python_policy_hook();

// The message of a scenario naming a Python policy in a program without the hook.
inline constexpr std::string_view kNoPythonSupport =
    "this program was built without Python support (configure with -DPHEROMESH_PYTHON=ON, which needs pybind11 and "
    "the Python 3 development files: docs/python.md)";

}  // namespace pheromesh::core
