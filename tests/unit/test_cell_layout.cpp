// Who runs where and names whom in cells, on one host and over several
// (cli/cell_layout.hpp; docs/dds.md, "Cell discovery").
#include <gtest/gtest.h>

#include <set>

#include "../../cli/cell_layout.hpp"
#include "pheromesh/bus/cell_discovery.hpp"

namespace pheromesh::cli {
namespace {

SwarmShape three_hosts(uint32_t replicas = 1) {
  SwarmShape s;
  s.regions = 4;
  s.uavs = 10;
  s.replicas = replicas;
  s.domain = 5;
  s.hosts = 3;
  s.ground_host = 0;
  s.addresses = {"10.0.0.1", "10.0.0.2", "10.0.0.3"};
  return s;
}

TEST(CellLayout, AUavRunsOnTheHostOfItsHomePlaceAgent) {
  const CellLayout l(three_hosts());
  // Place agent R on host R % 3; UAV U's home is U % 4.
  EXPECT_EQ(l.host_of("place", 3), 0U);
  for (uint32_t u = 0; u < 10; ++u) {
    EXPECT_EQ(l.host_of("uav", u), l.host_of("place", u % 4)) << "uav " << u;
  }
  EXPECT_EQ(l.host_of("uav", 7), 0U);  // home 3, on host 0
  EXPECT_EQ(l.host_of("ground", 0), 0U);
  // A standby runs on another host than its primary.
  const CellLayout s(three_hosts(2));
  for (uint32_t r = 0; r < 4; ++r) EXPECT_NE(s.host_of("place", r, 1), s.host_of("place", r, 0)) << "region " << r;
}

TEST(CellLayout, HubIndicesAreCountedOnEachHostByItself) {
  const CellLayout l(three_hosts(2));
  // Host 0: the ground station 0, place-0 1, place-3 2, place-2.r1 3.
  EXPECT_EQ(l.hub("ground", 0).index, 0U);
  EXPECT_EQ(l.hub("place", 0).index, 1U);
  EXPECT_EQ(l.hub("place", 3).index, 2U);
  EXPECT_EQ(l.hub("place", 2, 1).index, 3U);
  EXPECT_EQ(l.hub("place", 2, 1).address, "10.0.0.1");
  // Host 1 has no ground station: place-1 0, place-0.r1 1, place-3.r1 2.
  EXPECT_EQ(l.hub("place", 1).index, 0U);
  EXPECT_EQ(l.hub("place", 0, 1).index, 1U);
  EXPECT_EQ(l.hub("place", 3, 1).index, 2U);
  EXPECT_EQ(l.hub("place", 3, 1).address, "10.0.0.2");
  EXPECT_EQ(l.hubs_on(0), 4U);
  EXPECT_EQ(l.hubs_on(1), 3U);
  EXPECT_EQ(l.hubs_on(2), 2U);  // place-2, place-1.r1
  EXPECT_EQ(l.most_hubs_on_a_host(), 4U);
  // No two hubs share an address and an index.
  std::set<std::pair<std::string, uint32_t>> seen{{l.hub("ground", 0).address, l.hub("ground", 0).index}};
  for (uint32_t k = 0; k < 2; ++k) {
    for (uint32_t r = 0; r < 4; ++r) {
      const auto h = l.hub("place", r, k);
      EXPECT_TRUE(seen.insert({h.address, h.index}).second) << "place " << r << " replica " << k;
    }
  }
}

TEST(CellLayout, AUavNamesItsGatewaysByTheirHostsAddressAndBindsItsOwn) {
  const CellLayout l(three_hosts());
  // UAV 6: home 2 (host 2, index 0 there), backup 3 (host 0, index 2), in
  // reserve in a realtime run.
  const bus::CellDiscovery c = l.cell_of("uav", 6);
  EXPECT_EQ(bus::format_cell(c), "peers=10.0.0.3:0;reserve=10.0.0.1:2;iface=10.0.0.3");
  EXPECT_TRUE(bus::check_cell(c).ok());
  // What a process parses back is what it was given.
  const auto back = bus::parse_cell(bus::format_cell(c), 5);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->interface_address, "10.0.0.3");
  EXPECT_EQ(back->reserve.at(0).address, "10.0.0.1");
  // A hub names the ground station and every other place agent where they run.
  EXPECT_EQ(bus::format_cell(l.cell_of("place", 1)),
            "index=0;peers=10.0.0.1:0,10.0.0.1:1,10.0.0.3:0,10.0.0.1:2;iface=10.0.0.2");
  EXPECT_EQ(bus::format_cell(l.cell_of("ground", 0)),
            "index=0;peers=10.0.0.1:1,10.0.0.2:0,10.0.0.3:0,10.0.0.1:2;iface=10.0.0.1");
}

TEST(CellLayout, OnOneHostEverythingIsOnLoopbackAndTheCellTextStaysShort) {
  SwarmShape s;
  s.regions = 4;
  s.uavs = 10;
  const CellLayout l(s);
  EXPECT_EQ(bus::format_cell(l.cell_of("uav", 6)), "peers=127.0.0.1:3;reserve=127.0.0.1:4");
  EXPECT_EQ(l.most_hubs_on_a_host(), 5U);
  EXPECT_EQ(CellLayout::member_id(6), 126U);  // past every index a hub can have
}

TEST(CellLayout, TooManyHubsOnAHostOrPortsInTheEphemeralRangeAreRefusedWithTheReason) {
  SwarmShape s;
  s.regions = 70;
  s.uavs = 10;
  s.replicas = 2;  // 141 hubs on one host
  auto err = CellLayout(s).check(false);
  ASSERT_TRUE(err.has_value());
  EXPECT_NE(err->find("more hosts"), std::string::npos) << *err;
  // Over two hosts each has 71 or 70: within the limit.
  s.hosts = 2;
  s.addresses = {"10.0.0.1", "10.0.0.2"};
  EXPECT_EQ(CellLayout(s).check(false), std::nullopt);
  SwarmShape far;
  far.regions = 4;
  far.uavs = 1000;
  far.domain = 95;  // Fast DDS UAV 999's ports: 7410 + 250 * 95 + 2 * 1119, past 32767
  err = CellLayout(far).check(true);
  ASSERT_TRUE(err.has_value());
  EXPECT_NE(err->find("ephemeral"), std::string::npos) << *err;
  EXPECT_EQ(CellLayout(far).check(false), std::nullopt) << "Cyclone members take ports from the kernel";
}

TEST(CellLayout, AMonitorNamesEveryHubIndexOnEveryHost) {
  const bus::CellDiscovery m = monitor_cell(3, 2, {"10.0.0.1", "10.0.0.2"}, "10.0.0.9");
  EXPECT_EQ(bus::format_cell(m), "peers=10.0.0.1:0,10.0.0.1:1,10.0.0.2:0,10.0.0.2:1;iface=10.0.0.9");
  EXPECT_EQ(bus::format_cell(monitor_cell(3, 2, {}, "127.0.0.1")), "peers=127.0.0.1:0,127.0.0.1:1");
}

TEST(CellLayout, LoopbackIsALocalAddressAndTheRouteToItLeavesFromIt) {
  EXPECT_TRUE(is_local_address("127.0.0.1"));
  EXPECT_FALSE(is_local_address("192.0.2.77")) << "TEST-NET-1 is nobody's address";
  EXPECT_FALSE(is_local_address("not-an-address"));
  EXPECT_EQ(local_address_towards("127.0.0.1").value_or(""), "127.0.0.1");
  EXPECT_FALSE(local_address_towards("nowhere").has_value());
}

}  // namespace
}  // namespace pheromesh::cli
