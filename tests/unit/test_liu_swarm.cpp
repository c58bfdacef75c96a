// Liu 2022 Sec. 5 simulation (liu_swarm): determinism, the mower's coverage, the
// EU series, confirmations, and configuration errors.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "pheromesh/liu/swarm.hpp"
#include "pheromesh/liu/tpm.hpp"

namespace pheromesh::core {
namespace {

constexpr LiuPolicy kAllPolicies[] = {LiuPolicy::kEsustpm, LiuPolicy::kLawnmower, LiuPolicy::kRandom,
                                      LiuPolicy::kBoids, LiuPolicy::kGuidedBoids, LiuPolicy::kEsustpmDisperse};

LiuSwarmResult run_ok(const LiuSwarmConfig& c, uint64_t seed) {
  auto r = run_liu_swarm(c, seed);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
  return r.ok() ? r.value() : LiuSwarmResult{};
}

TEST(LiuSwarm, SameSeedGivesTheSameRunForEveryPolicy) {
  for (const LiuPolicy policy : kAllPolicies) {
    LiuSwarmConfig c;
    c.policy = policy;
    const LiuSwarmResult a = run_ok(c, 7);
    const LiuSwarmResult b = run_ok(c, 7);
    EXPECT_EQ(a.visited_cells, b.visited_cells) << to_string(policy);
    EXPECT_EQ(a.eu_per_cycle, b.eu_per_cycle) << to_string(policy);
    EXPECT_EQ(a.final_tpm, b.final_tpm) << to_string(policy);
    EXPECT_EQ(a.confirmation_cycle, b.confirmation_cycle) << to_string(policy);
    EXPECT_EQ(a.observations, b.observations) << to_string(policy);
  }
}

TEST(LiuSwarm, DifferentSeedsGiveDifferentRandomSearches) {
  LiuSwarmConfig c;
  c.policy = LiuPolicy::kRandom;
  EXPECT_NE(run_ok(c, 1).final_tpm, run_ok(c, 2).final_tpm);
}

TEST(LiuSwarm, SeriesHoldThePriorAndOneEntryPerCycle) {
  LiuSwarmConfig c;
  const LiuSwarmResult r = run_ok(c, 3);
  const std::size_t n = c.params.cycles + 1;
  EXPECT_EQ(r.eu_per_cycle.size(), n);
  EXPECT_EQ(r.visited_per_cycle.size(), n);
  EXPECT_EQ(r.found_per_cycle.size(), n);
  EXPECT_EQ(r.visited_per_cycle.back(), r.visited_cells);
  EXPECT_DOUBLE_EQ(r.eu_per_cycle.back(), r.final_eu);
  EXPECT_EQ(r.final_tpm.size(), 100U);
  for (std::size_t k = 1; k < n; ++k) EXPECT_GE(r.visited_per_cycle[k], r.visited_per_cycle[k - 1]);
}

TEST(LiuSwarm, LawnmowerVisitsAllHundredCells) {
  LiuSwarmConfig c;
  c.policy = LiuPolicy::kLawnmower;
  EXPECT_EQ(run_ok(c, 1).visited_cells, 100);
  c.targets.clear();
  EXPECT_EQ(run_ok(c, 2).visited_cells, 100);
}

TEST(LiuSwarm, NoiselessMowerWithoutTargetsReproducesTableTwoUncertainty) {
  // 10 mowers, one row each, 2000 m in 200 s: cells 1-8 of a row entered
  // twice, 0 and 9 once, every observation a miss: 10·(8·0.52181 + 2·0.52989).
  LiuSwarmConfig c;
  c.policy = LiuPolicy::kLawnmower;
  c.sensor = LiuSensor::kAlgorithm1;
  c.targets.clear();
  const LiuSwarmResult r = run_ok(c, 1);
  EXPECT_NEAR(r.final_eu, 52.34, 0.005);
  EXPECT_EQ(r.observations, 180);
}

TEST(LiuSwarm, UncertaintyStartsAtThePriorsUncertainty) {
  for (const LiuPrior prior : {LiuPrior::kUniform, LiuPrior::kAccurate, LiuPrior::kWrong}) {
    LiuSwarmConfig c;
    c.prior = prior;
    if (prior == LiuPrior::kWrong) c.targets = {kLiuUnexpectedTarget};
    const LiuSwarmResult r = run_ok(c, 5);
    ASSERT_FALSE(r.eu_per_cycle.empty());
    EXPECT_DOUBLE_EQ(r.eu_per_cycle.front(), environmental_uncertainty(liu_prior_map(c))) << to_string(prior);
  }
  LiuSwarmConfig uniform;
  EXPECT_DOUBLE_EQ(run_ok(uniform, 5).eu_per_cycle.front(), 50.0);  // 100 cells · 0.5
}

TEST(LiuSwarm, AccuratePriorPutsTheMostMassOnTheTargetCell) {
  LiuSwarmConfig c;
  c.prior = LiuPrior::kAccurate;
  c.targets = {Vec2{400.0, 500.0}};
  const std::vector<double> m = liu_prior_map(c);
  std::size_t best = 0;
  for (std::size_t i = 1; i < m.size(); ++i) {
    if (m[i] > m[best]) best = i;
  }
  EXPECT_EQ(best, 5U * 10U + 4U);    // cell (4, 5)
  EXPECT_NEAR(m[best], 0.1466, 1e-3);  // (Φ(0.5) - Φ(-0.5))² with σ0 = 1 cell, α = 1
}

TEST(LiuSwarm, NoPolicyFindsMoreTargetsThanThereAre) {
  for (const LiuPolicy policy : kAllPolicies) {
    for (const LiuSensor sensor : {LiuSensor::kNoisy, LiuSensor::kAlgorithm1}) {
      for (uint64_t seed = 1; seed <= 3; ++seed) {
        LiuSwarmConfig c;
        c.policy = policy;
        c.sensor = sensor;
        const LiuSwarmResult r = run_ok(c, seed);
        EXPECT_LE(r.targets_found, 3U) << to_string(policy);
        std::size_t confirmed = 0;
        for (const auto& cycle : r.confirmation_cycle) confirmed += cycle.has_value() ? 1U : 0U;
        EXPECT_EQ(confirmed, r.targets_found);
        EXPECT_EQ(r.found_per_cycle.back(), r.targets_found);
      }
    }
  }
}

TEST(LiuSwarm, PerfectSensorConfirmsATargetWhenAUavEntersItsCell) {
  // The mower of row 0 starts at (50, 50) and flies +x at 10 m/s: it enters
  // cell (5, 0) after 450 m, in cycle 45 (46 if rounding puts the crossing
  // just after the cycle's end).
  LiuSwarmConfig c;
  c.policy = LiuPolicy::kLawnmower;
  c.params.p_detection = 1.0;
  c.params.p_false_alarm = 0.0;
  c.targets = {Vec2{550.0, 50.0}};
  const LiuSwarmResult r = run_ok(c, 1);
  EXPECT_EQ(r.targets_found, 1U);
  ASSERT_TRUE(r.confirmation_cycle[0].has_value());
  EXPECT_GE(*r.confirmation_cycle[0], 45U);
  EXPECT_LE(*r.confirmation_cycle[0], 46U);
  EXPECT_EQ(r.all_found_cycle, r.confirmation_cycle[0]);
  EXPECT_EQ(r.false_confirmations, 0U);
}

TEST(LiuSwarm, PerfectSensorEsustpmConfirmsTheTargetBesideItsStart) {
  // UAV 9 starts at (200, 500), the corner of cell (2, 5); a target in
  // (3, 5) is a neighbour cell of several UAVs.
  LiuSwarmConfig c;
  c.params.p_detection = 1.0;
  c.params.p_false_alarm = 0.0;
  c.targets = {Vec2{350.0, 550.0}};
  const LiuSwarmResult r = run_ok(c, 1);
  EXPECT_EQ(r.targets_found, 1U);
  EXPECT_EQ(r.false_confirmations, 0U);
}

TEST(LiuSwarm, WithoutTargetsNothingIsFound) {
  LiuSwarmConfig c;
  c.targets.clear();
  const LiuSwarmResult r = run_ok(c, 4);
  EXPECT_EQ(r.targets_found, 0U);
  EXPECT_FALSE(r.all_found_cycle.has_value());
}

TEST(LiuSwarm, BoidsAtRestOnTheStartLatticeNeverLeaveTheirCells) {
  // Why UAVs start with a random heading: at rest, separation and cohesion
  // cancel on Liu 2022 Sec. 5's 100 m lattice.
  LiuSwarmConfig c;
  c.policy = LiuPolicy::kBoids;
  c.start_velocity = LiuStartVelocity::kRest;
  EXPECT_EQ(run_ok(c, 1).visited_cells, 10);
  c.start_velocity = LiuStartVelocity::kRandomHeading;
  EXPECT_GT(run_ok(c, 1).visited_cells, 10);
}

TEST(LiuSwarm, ConfigurationsThatCannotRunAreRejected) {
  LiuSwarmConfig few_starts;
  few_starts.starts.resize(3);
  EXPECT_FALSE(run_liu_swarm(few_starts, 1).ok());

  LiuSwarmConfig crowded_mower;
  crowded_mower.policy = LiuPolicy::kLawnmower;
  crowded_mower.params.uav_count = 11;
  EXPECT_FALSE(run_liu_swarm(crowded_mower, 1).ok());

  LiuSwarmConfig always_false_alarm;
  always_false_alarm.params.p_false_alarm = 1.0;  // Liu 2022 eq. (5) divides by 1 - Pf
  EXPECT_FALSE(run_liu_swarm(always_false_alarm, 1).ok());

  LiuSwarmConfig outside;
  outside.targets = {Vec2{-5.0, 100.0}};
  EXPECT_FALSE(run_liu_swarm(outside, 1).ok());

  LiuSwarmConfig flat_prior;
  flat_prior.prior = LiuPrior::kAccurate;
  flat_prior.prior_sigma_cells = 0.0;
  EXPECT_FALSE(run_liu_swarm(flat_prior, 1).ok());
}

TEST(LiuSwarm, MowerWithFewerUavsThanRowsStillCoversTheMap) {
  // Five mowers, two rows each: the climb at the border keeps Liu 2022 eq. (14)'s sweep.
  LiuSwarmConfig c;
  c.policy = LiuPolicy::kLawnmower;
  c.params.uav_count = 5;
  c.params.cycles = 400;
  EXPECT_EQ(run_ok(c, 1).visited_cells, 100);
}

}  // namespace
TEST(LiuSwarm, EveryPolicyLooksAtEveryCellItVisitsButItsStartCell) {
  // The fair-baseline bookkeeping: the sensor and the TPM update do not depend
  // on the search; every visited cell but the start cells was looked at, and
  // each look moved its cell's P off the prior 0.5 (a miss lowers it, a
  // detection raises it; P = 0.5 again after a look is a measure-zero event).
  for (const LiuPolicy policy : kAllPolicies) {
    LiuSwarmConfig c;
    c.policy = policy;
    c.params.cycles = 30;
    const LiuSwarmResult r = run_ok(c, 3);
    int64_t touched = 0;
    for (const double v : r.final_tpm) touched += v != c.params.initial_probability ? 1 : 0;
    EXPECT_GE(touched, r.visited_cells - static_cast<int64_t>(c.params.uav_count)) << to_string(policy);
    EXPECT_GE(r.observations, touched) << to_string(policy);
  }
}

TEST(LiuSwarm, TheDisperseVariantVisitsMoreCellsThanEsustpmOnTheSameSeeds) {
  // Liu 2022 Algorithm 1's sensor, seeds 1-3: ESUSTPM's lattice drifts as one body, the
  // variant without the neighbour pull spreads (liu-table2 over 10 seeds: 63 vs 97).
  int64_t esustpm = 0, disperse = 0;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    LiuSwarmConfig c;
    c.sensor = LiuSensor::kAlgorithm1;
    esustpm += run_ok(c, seed).visited_cells;
    c.policy = LiuPolicy::kEsustpmDisperse;
    disperse += run_ok(c, seed).visited_cells;
  }
  EXPECT_GT(disperse, esustpm + 3 * 15);  // more than 15 cells a run on average
}

}  // namespace pheromesh::core
