// `pheromesh run`'s warning when a swarm exceeds what this host held on time
// in the scale benchmark (launch/host_fit.hpp, header-only for these tests).
#include <gtest/gtest.h>

#include "launch/host_fit.hpp"

namespace pheromesh::cli {
namespace {

TEST(HostFit, ASwarmWithinTheMeasuredFigureGetsNoWarning) {
  EXPECT_FALSE(host_fit_warning(100, 5.0, 2, "cyclone", false).has_value());
  EXPECT_FALSE(host_fit_warning(10, 10.0, 2, "cyclone", false).has_value());
}

TEST(HostFit, TooManyProcessesNameTheMeasuredDiscoveryLimitAndTheServerForFastDds) {
  const auto w = host_fit_warning(250, 1.0, 2, "fastdds", false);
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("250 UAV processes"), std::string::npos) << *w;
  EXPECT_NE(w->find("--discovery-server"), std::string::npos) << *w;
  // Twice the cores, twice the processes measured.
  EXPECT_FALSE(host_fit_warning(200, 1.0, 4, "cyclone", false).has_value());
}

TEST(HostFit, TooFastSuggestsARateThatFits) {
  const auto w = host_fit_warning(100, 10.0, 2, "cyclone", false);
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("try --rate 5.0"), std::string::npos) << *w;
  EXPECT_EQ(w->find("processes:"), std::string::npos) << "the count itself is within the figure: " << *w;
}

TEST(HostFit, CellsHoldWhatTheirBenchmarkMeasuredAndTheFlatProfileSuggestsThem) {
  EXPECT_FALSE(host_fit_warning(2000, 5.0, 2, "cyclone", false, /*cells=*/true).has_value());
  const auto cyclone = host_fit_warning(2001, 5.0, 2, "cyclone", false, /*cells=*/true);
  ASSERT_TRUE(cyclone.has_value());
  EXPECT_NE(cyclone->find("held 2000 UAVs on time over Cyclone"), std::string::npos) << *cyclone;
  EXPECT_FALSE(host_fit_warning(1000, 5.0, 2, "fastdds", false, /*cells=*/true).has_value());
  const auto fast = host_fit_warning(1001, 5.0, 2, "fastdds", false, /*cells=*/true);
  ASSERT_TRUE(fast.has_value());
  EXPECT_NE(fast->find("held 1000 UAVs on time over Fast DDS"), std::string::npos) << *fast;
  const auto flat = host_fit_warning(300, 1.0, 2, "cyclone", false);
  ASSERT_TRUE(flat.has_value());
  EXPECT_NE(flat->find("cells, the default profile"), std::string::npos) << *flat;
}

TEST(HostFit, ACellsSwarmAboveItsCountIsToldToAddHostsNotToSlowDown) {
  const auto w = host_fit_warning(2500, 5.0, 2, "cyclone", false, /*cells=*/true);
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("--hosts"), std::string::npos) << *w;
  EXPECT_EQ(w->find("--rate"), std::string::npos) << "a lower rate does not make discovery hold: " << *w;
  // Within the count, the 300 UAVs at 5 Hz in cells are within the
  // flight budget too (2000 x 5 UAV ticks per second on Cyclone).
  EXPECT_FALSE(host_fit_warning(300, 5.0, 2, "cyclone", false, /*cells=*/true).has_value());
}

// /proc/self/cgroup as this machine, a systemd host on cgroup v2 and a
// container on cgroup v1 print it.
constexpr const char* kRootV1 = "9:name=systemd:/\n4:memory:/process_api/49e1\n2:cpuacct:/\n1:cpu:/\n0::/\n";
constexpr const char* kSystemdV2 = "0::/user.slice/user-1000.slice/session-3.scope\n";
constexpr const char* kContainerV1 = "3:cpu,cpuacct:/machine.slice/libpod-4f2a.scope\n1:name=systemd:/\n";

TEST(HubWeight, AutogroupAppliesOnlyWhenOnAndInTheRootCpuCgroup) {
  EXPECT_TRUE(autogroup_applies("1\n", kRootV1));
  EXPECT_TRUE(autogroup_applies("1", "0::/\n"));
  EXPECT_FALSE(autogroup_applies("0\n", kRootV1));
  EXPECT_FALSE(autogroup_applies("", kRootV1));  // a kernel without it: no such file
  EXPECT_FALSE(autogroup_applies("1\n", kSystemdV2));
  // The v1 hierarchy with the cpu controller decides, not the v2 line.
  EXPECT_FALSE(autogroup_applies("1\n", std::string(kContainerV1) + "0::/\n"));
  EXPECT_FALSE(autogroup_applies("1\n", ""));
}

TEST(HubWeight, ABigRealtimeSwarmIsWarnedWhereThePlaceAgentsCannotWeighMore) {
  const auto w = hub_weight_warning(2000, /*realtime=*/true, "1\n", kSystemdV2);
  ASSERT_TRUE(w.has_value());
  EXPECT_NE(w->find("2000 UAV processes"), std::string::npos) << *w;
  EXPECT_NE(w->find("docs/deployment.md"), std::string::npos) << *w;
  EXPECT_FALSE(hub_weight_warning(2000, true, "1\n", kRootV1).has_value());
  EXPECT_FALSE(hub_weight_warning(2000, /*realtime=*/false, "0\n", kSystemdV2).has_value());  // lockstep takes turns
  EXPECT_FALSE(hub_weight_warning(kHubsStarveAbove, true, "0\n", kSystemdV2).has_value());
  EXPECT_TRUE(hub_weight_warning(kHubsStarveAbove + 1, true, "0\n", kRootV1).has_value());
}

}  // namespace
}  // namespace pheromesh::cli
