#include "experiment.hpp"

namespace pheromesh::cli::experiments {

std::vector<Experiment> all_experiments() {
  std::vector<Experiment> all;
  for (auto family : {shao_experiments, shao_navigation_experiments, liu_experiments, duan_experiments, ravankar_experiments, shostak_experiments}) {
    for (auto& e : family()) all.push_back(std::move(e));
  }
  return all;
}

}  // namespace pheromesh::cli::experiments
