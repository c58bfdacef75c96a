// A summary of measured durations (or any samples): count, mean and
// nearest-rank percentiles. Benchmarks and metrics.json print these.
#pragma once

#include <cstddef>
#include <vector>

namespace pheromesh::core {

struct SampleSummary {
  std::size_t n = 0;
  double mean = 0;
  double p50 = 0;
  double p90 = 0;
  double p99 = 0;
  double max = 0;
};

// Nearest rank: the q-percentile is the smallest sample with at least a share
// q of the samples at or below it. All zero for no samples.
SampleSummary summarize(std::vector<double> samples);

}  // namespace pheromesh::core
