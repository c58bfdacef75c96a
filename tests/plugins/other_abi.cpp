// A library that says it was built for another plugin ABI version: the
// loader must refuse it naming both versions, before it asks for the entry.
#include <cstdint>

#include "pheromesh/core/policy_plugin.hpp"

extern "C" __attribute__((visibility("default"))) uint32_t pheromesh_policy_plugin_abi() {
  return pheromesh::core::kPolicyPluginAbi + 998;
}
extern "C" __attribute__((visibility("default"))) uint64_t pheromesh_policy_plugin_layout() {
  return pheromesh::core::policy_plugin_layout();
}
extern "C" __attribute__((visibility("default"))) const pheromesh::core::PluginPolicy* pheromesh_policy_plugin() {
  return nullptr;
}
