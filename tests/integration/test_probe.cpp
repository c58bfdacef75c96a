// pheromesh-test-probe ends by its own bounds (issue 28): with 100 secured
// participants, probes blocked in DDS calls ignored SIGTERM and their
// --timeout. `--stall` blocks before the bus is made, deaf to signals, as
// such a call does; the watchdog must end the process anyway. Domain 124.
#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers

namespace {

std::string probe(const std::string& extra) { return kBin + "/pheromesh-test-probe --domain 124 " + extra; }

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

TEST(Probe, ADiscoverProbeThatHearsNobodyEndsAtItsTimeoutSayingWhoIsMissing) {
  const auto t0 = Clock::now();
  const Output o = run(probe("discover --id 0 --expect 2 --timeout 1.5"));
  const double took = seconds_since(t0);
  EXPECT_EQ(o.exit_code, 1) << o.text;
  EXPECT_NE(o.text.find("timeout: discovered 1 of 2 (not heard: 1)"), std::string::npos) << o.text;
  EXPECT_EQ(o.text.find("watchdog"), std::string::npos) << "it ended by itself: " << o.text;
  EXPECT_GE(took, 1.5);
  EXPECT_LT(took, 1.5 + 2.0 + 3.0) << "--timeout 1.5, the watchdog's grace 2 s, 3 s of slack for a loaded host";
}

TEST(Probe, AProbeBlockedPastItsTimeoutIsEndedByItsWatchdog) {
  // Blocked for 60 s; --timeout 1 s. Without the watchdog it would run 60 s.
  const auto t0 = Clock::now();
  const Output o = run(probe("--stall 60 discover --id 0 --expect 2 --timeout 1"));
  const double took = seconds_since(t0);
  EXPECT_EQ(o.exit_code, 1) << o.text;
  EXPECT_NE(o.text.find("probe watchdog: did not end within its --timeout"), std::string::npos) << o.text;
  EXPECT_LT(took, 1.0 + 2.0 + 3.0) << o.text;
}

TEST(Probe, AProbeBlockedWhenSigtermArrivesEndsWithinTheGrace) {
  const std::string out = out_dir("probe-sigterm");
  const Background p =
      start({"/bin/sh", "-c", "exec " + probe("--stall 60 idle --id 0") + " 2>&1"}, out + "/probe.txt");
  ASSERT_TRUE(wait_for_text(out + "/probe.txt", "probe: stalling for", std::chrono::seconds(30))) << slurp(out + "/probe.txt");
  const auto t0 = Clock::now();
  ASSERT_EQ(kill(p.pid, SIGTERM), 0);
  const int code = wait_exit(p.pid, std::chrono::seconds(30));
  const double took = seconds_since(t0);
  EXPECT_EQ(code, 5) << slurp(p.out_path);
  EXPECT_NE(slurp(p.out_path).find("probe watchdog: did not end within 2 s of SIGINT/SIGTERM"), std::string::npos)
      << slurp(p.out_path);
  EXPECT_LT(took, 2.0 + 3.0);
}
