// The policy table (policy_table.hpp): one line per built-in policy, naming
// the entry its room defines. The shared core includes no room: each line
// declares the entry it lists.
#include "pheromesh/core/policy_table.hpp"

#include <array>
#include <stdexcept>

#include "pheromesh/core/plugin_loader.hpp"
#include "pheromesh/core/python_policy.hpp"

namespace pheromesh::core {

// X(entry): one line per built-in policy, the entry its room defines
// (papers/<paper>/src/scenario.cpp). A scenario without `policy` runs
// kDefaultPolicy (scenario.hpp).
#define PHEROMESH_BUILTIN_POLICIES(X) \
  X(kShaoSearchPolicy)                \
  X(kShaoNavigationPolicy)            \
  X(kLiuPolicy)                       \
  X(kShostakPolicy)                   \
  X(kRavankarPolicy)                  \
  X(kDuanPolicy)

#define PHEROMESH_DECLARE_ENTRY(entry) extern const PolicyEntry entry;
PHEROMESH_BUILTIN_POLICIES(PHEROMESH_DECLARE_ENTRY)
#undef PHEROMESH_DECLARE_ENTRY

namespace {
#define PHEROMESH_LIST_ENTRY(entry) &(entry),
constexpr std::array kBuiltin{PHEROMESH_BUILTIN_POLICIES(PHEROMESH_LIST_ENTRY)};
#undef PHEROMESH_LIST_ENTRY
}  // namespace
#undef PHEROMESH_BUILTIN_POLICIES

std::span<const PolicyEntry* const> policy_table() { return kBuiltin; }

const PolicyEntry* find_policy(std::string_view name) {
  for (const PolicyEntry* e : kBuiltin) {
    if (e->name == name) return e;
  }
  if (const PolicyEntry* e = find_plugin_policy(name)) return e;  // the plugins this process loaded (plugin_loader.hpp)
  // The Python policies this process loaded (python_policy.hpp).
  const PythonPolicyHook* hook = python_policy_hook();
  return hook == nullptr ? nullptr : hook->find(name);
}

namespace {
const PythonPolicyHook* g_python_hook = nullptr;  // set once at a program's start
}  // namespace

void set_python_policy_hook(const PythonPolicyHook* hook) { g_python_hook = hook; }
const PythonPolicyHook* python_policy_hook() { return g_python_hook; }

std::string policy_names() {
  std::string out;
  for (const PolicyEntry* e : kBuiltin) out += (out.empty() ? "" : ", ") + std::string(e->name);
  return out;
}

const PolicyEntry& policy_entry(const ScenarioConfig& s) {
  if (const PolicyEntry* e = find_policy(s.policy)) return *e;
  throw std::logic_error("scenario '" + s.name + "': policy '" + s.policy + "' has no entry in the policy table (" +
                         policy_names() + ")");
}

// ------------------------------------------------------------ through the table
PolicyTraits policy_traits(const ScenarioConfig& s) {
  const PolicyEntry& e = policy_entry(s);
  PolicyTraits t = e.traits(s);
  t.broadcasts = e.broadcasts;
  t.layer_ranges.resize(t.layers.size(), ValueRange{0.0F, kMaxLayerValue});
  // Every UAV's start cell once: uav_start is asked for each state and each
  // deposit a gateway judges, and start_cell walks the whole start area.
  if (t.starts.size() < s.uavs) {
    const std::vector<Cell> all = start_cells(s);
    t.starts.insert(t.starts.end(), all.begin() + static_cast<std::ptrdiff_t>(t.starts.size()), all.end());
  }
  return t;
}

Cell uav_start(const ScenarioConfig& s, const PolicyTraits& traits, uint32_t id) {
  return id < traits.starts.size() ? traits.starts[id] : start_cell(s, id);
}

std::unique_ptr<UavPolicy> make_uav_policy(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                           uint32_t id) {
  return policy_entry(s).make_uav(s, geo, world, id);
}

std::unique_ptr<PlaceModel> make_place_model(const ScenarioConfig& s, const MapGeometry& geo, RegionId region) {
  return policy_entry(s).make_place(s, geo, region);
}

std::map<std::string, double> field_summary(const ScenarioConfig& s, const FieldLookup& value) {
  const PolicyEntry& e = policy_entry(s);
  if (e.field_summary == nullptr) return {};
  return e.field_summary(s, value);
}

}  // namespace pheromesh::core
