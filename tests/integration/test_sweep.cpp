// `pheromesh sweep --distributed` (issue 26): a sampled run of a sweep
// flown as real processes in lockstep on Cyclone DDS gives the simulator's
// numbers and field. One small run (small-test, 40 ticks) on domain 39; the
// sweep's tables, resumption and the failing check are unit tests
// (tests/unit/test_sweep.cpp).
#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers

TEST(Cli, SweepFliesASampledRunInLockstepOnCycloneAndFindsItEqualToTheSimulator) {
  const std::string out = out_dir("sweep-distributed");
  const std::string cmd = kBin +
                          "/pheromesh sweep small-test --set shao.aco.alpha=1,2 --seeds 1-2 --ticks 40 --jobs 2 " +
                          "--distributed --distributed-sample 1 --dds cyclone --domain 39 --out " + out;
  const Output o = run(cmd);
  ASSERT_EQ(o.exit_code, 0) << o.text;
  EXPECT_NE(o.text.find("distributed c000-s1 (shao.aco.alpha=1, seed 1): lockstep == sim: yes"), std::string::npos)
      << o.text;
  EXPECT_NE(o.text.find("runs/s"), std::string::npos) << o.text;
  const json m = read_metrics(out + "/distributed/c000-s1/lockstep");
  ASSERT_FALSE(m.is_null()) << o.text;
  EXPECT_EQ(m["clock"], "lockstep");
  EXPECT_EQ(m["ticks"], 40);
  EXPECT_EQ(m["seed"], 1);
  EXPECT_EQ(m["processes_crashed"], 0);
  EXPECT_EQ(slurp(out + "/distributed/c000-s1/lockstep/final_field.txt"),
            slurp(out + "/distributed/c000-s1/sim/final_field.txt"));
  EXPECT_NE(slurp(out + "/sweep.md").find("1 of 1 sampled runs"), std::string::npos);
}
