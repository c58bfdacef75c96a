// Seeded, per-agent random streams. Platform-independent (no std::
// distributions), so a seed gives the same numbers everywhere.
#pragma once

#include <cstdint>
#include <string_view>

namespace pheromesh::core {

// SplitMix64 step; used to derive stream seeds.
uint64_t splitmix64(uint64_t& state);

// Seed of the stream of agent `id` of kind `kind` ("uav", "place", ...) in a
// run seeded with `run_seed`. Different (kind, id) pairs give independent streams.
uint64_t stream_seed(uint64_t run_seed, std::string_view kind, uint32_t id);

// xoshiro256** generator.
class Rng {
 public:
  explicit Rng(uint64_t seed);
  uint64_t next();
  double uniform01();                 // [0, 1)
  uint32_t uniform_below(uint32_t n);  // [0, n), n > 0, unbiased

 private:
  uint64_t s_[4];
};

}  // namespace pheromesh::core
