// Seeded random streams: SplitMix64 for seeding, xoshiro256** for the stream
// (Blackman & Vigna, https://prng.di.unimi.it/). No std:: distributions, so the
// numbers are the same on every platform and standard library.
#include "pheromesh/core/rng.hpp"

#include <cassert>

namespace pheromesh::core {

namespace {

constexpr uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

// FNV-1a, 64 bit: turns the agent kind into a number.
constexpr uint64_t fnv1a64(std::string_view s) {
  uint64_t h = 0xcbf29ce484222325ULL;
  for (const char ch : s) {
    h ^= static_cast<uint8_t>(ch);
    h *= 0x100000001b3ULL;
  }
  return h;
}

}  // namespace

uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

uint64_t stream_seed(uint64_t run_seed, std::string_view kind, uint32_t id) {
  // Chain of SplitMix64 steps, mixing in the run seed, then the kind, then the
  // id. The last step's output is a bijection of its state, and the state is
  // (something fixed by run_seed and kind) XOR id, so for one run seed and one
  // kind, different ids always give different seeds.
  uint64_t state = run_seed;
  state = splitmix64(state) ^ fnv1a64(kind);
  state = splitmix64(state) ^ uint64_t{id};
  return splitmix64(state);
}

Rng::Rng(uint64_t seed) {
  // Seeding with SplitMix64 as recommended by the xoshiro authors; four
  // consecutive outputs are never all zero (the output function is a bijection).
  uint64_t state = seed;
  for (uint64_t& word : s_) word = splitmix64(state);
}

uint64_t Rng::next() {
  // xoshiro256**
  const uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

double Rng::uniform01() {
  // Top 53 bits -> a multiple of 2^-53 in [0, 1).
  return static_cast<double>(next() >> 11) * 0x1.0p-53;
}

uint32_t Rng::uniform_below(uint32_t n) {
  assert(n > 0);
  if (n == 0) return 0;
  // Rejection: accept x only from [2^64 mod n, 2^64), whose size is a multiple
  // of n, so x % n is exactly uniform. (0 - n) % n == 2^64 mod n in uint64.
  const uint64_t bound = uint64_t{n};
  const uint64_t threshold = (0 - bound) % bound;
  for (;;) {
    const uint64_t x = next();
    if (x >= threshold) return static_cast<uint32_t>(x % bound);
  }
}

}  // namespace pheromesh::core
