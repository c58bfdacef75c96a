#include <stdexcept>

#include "experiment.hpp"
#include "flight.hpp"
#include "pheromesh/cliutil/scenario_paths.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"

namespace pheromesh::cli::experiments {

namespace {
core::ScenarioOverrides g_overrides;
uint32_t g_overridden_loads = 0;
}  // namespace

void set_overrides(core::ScenarioOverrides overrides) {
  g_overrides = std::move(overrides);
  g_overridden_loads = 0;
}

uint32_t overridden_loads() { return g_overridden_loads; }

core::Result<core::ScenarioConfig> load_shipped(const std::string& file) {
  if (!g_overrides.empty()) ++g_overridden_loads;
  return core::load_scenario(shipped_scenario(file), g_overrides);
}

std::vector<std::map<std::string, double>> simulate_scenario(const std::string& file, uint32_t runs,
                                                             const std::string& patch, const std::string& name) {
  auto loaded = load_shipped(file);
  if (!loaded) throw std::runtime_error(loaded.error().message);
  if (!patch.empty()) {
    loaded = core::patch_scenario(loaded.value(), patch, name.empty() ? file + " + " + patch : name);
    if (!loaded) throw std::runtime_error(loaded.error().message);
  }
  std::vector<std::map<std::string, double>> out;
  for (uint32_t run = 0; run < runs; ++run) {
    core::ScenarioConfig s = loaded.value();
    s.seed = run + 1;
    out.push_back(fly(s).field);
  }
  return out;
}

std::vector<double> field_samples(const std::vector<std::map<std::string, double>>& runs, const std::string& key) {
  std::vector<double> v;
  for (const auto& r : runs) {
    if (auto it = r.find(key); it != r.end()) v.push_back(it->second);
  }
  return v;
}

std::vector<Experiment> all_experiments() {
  std::vector<Experiment> all;
  for (auto family : {shao_experiments, shao_robustness_experiments, shao_navigation_experiments, liu_experiments, duan_experiments, ravankar_experiments, shostak_experiments}) {
    for (auto& e : family()) all.push_back(std::move(e));
  }
  return all;
}

}  // namespace pheromesh::cli::experiments
