// Seeded random streams: reproducible, independent per (kind, id), in range.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <set>

#include "pheromesh/core/rng.hpp"

namespace pheromesh::core {
namespace {

TEST(Rng, SplitMix64MatchesPublishedOutputsForSeedZero) {
  // Reference outputs of Vigna's splitmix64.c starting from state 0.
  uint64_t state = 0;
  EXPECT_EQ(splitmix64(state), 0xe220a8397b1dcdafULL);
  EXPECT_EQ(splitmix64(state), 0x6e789e6aa1b965f4ULL);
  EXPECT_EQ(splitmix64(state), 0x06c45d188009454fULL);
}

TEST(Rng, SameSeedGivesSameSequence) {
  Rng a(12345);
  Rng b(12345);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.next(), b.next()) << "at draw " << i;
  EXPECT_EQ(stream_seed(7, "uav", 3), stream_seed(7, "uav", 3));
}

TEST(Rng, DifferentSeedsGiveDifferentSequences) {
  Rng a(1);
  Rng b(2);
  int equal = 0;
  for (int i = 0; i < 100; ++i) equal += a.next() == b.next() ? 1 : 0;
  EXPECT_EQ(equal, 0);
}

TEST(Rng, DifferentKindOrIdGivesDifferentStreams) {
  const std::array<uint64_t, 5> seeds = {stream_seed(42, "uav", 0), stream_seed(42, "uav", 1), stream_seed(42, "place", 0),
                                         stream_seed(42, "place", 1), stream_seed(43, "uav", 0)};
  std::set<uint64_t> distinct(seeds.begin(), seeds.end());
  EXPECT_EQ(distinct.size(), seeds.size());
  // The first draws of the streams differ too.
  std::set<uint64_t> first_draws;
  for (const uint64_t s : seeds) first_draws.insert(Rng(s).next());
  EXPECT_EQ(first_draws.size(), seeds.size());
  // Many ids of one kind never collide (guaranteed by construction).
  std::set<uint64_t> many;
  for (uint32_t id = 0; id < 10000; ++id) many.insert(stream_seed(42, "uav", id));
  EXPECT_EQ(many.size(), 10000U);
}

TEST(Rng, Uniform01StaysInHalfOpenUnitInterval) {
  Rng r(99);
  double sum = 0.0;
  constexpr int kDraws = 100000;
  for (int i = 0; i < kDraws; ++i) {
    const double u = r.uniform01();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum += u;
  }
  // Mean 0.5, standard error sqrt(1/12 / 1e5) ~ 0.0009; 0.01 is > 10 sigma.
  EXPECT_NEAR(sum / kDraws, 0.5, 0.01);
}

TEST(Rng, UniformBelowStaysBelowBound) {
  Rng r(5);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(r.uniform_below(1), 0U);
  std::set<uint32_t> seen;
  for (int i = 0; i < 1000; ++i) {
    const uint32_t v = r.uniform_below(7);
    ASSERT_LT(v, 7U);
    seen.insert(v);
  }
  EXPECT_EQ(seen.size(), 7U);  // every value 0..6 shows up in 1000 draws
  for (int i = 0; i < 1000; ++i) ASSERT_LT(r.uniform_below(UINT32_MAX), UINT32_MAX);
  for (int i = 0; i < 1000; ++i) ASSERT_LT(r.uniform_below(0x80000001U), 0x80000001U);
}

TEST(Rng, UniformBelowIsRoughlyUniform) {
  Rng r(2024);
  std::array<int, 3> counts{};
  constexpr int kDraws = 30000;
  for (int i = 0; i < kDraws; ++i) ++counts[r.uniform_below(3)];
  // Expected 10000 each, sd sqrt(30000 * 1/3 * 2/3) ~ 82; 500 is ~6 sd.
  for (const int c : counts) EXPECT_NEAR(c, 10000, 500);
}

}  // namespace
}  // namespace pheromesh::core
