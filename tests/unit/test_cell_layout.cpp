// Who runs where and names whom in cells, on one host and over several
// (launch/cell_layout.hpp; docs/dds.md, "Cell discovery").
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <set>
#include <variant>

#include "launch/cell_command.hpp"
#include "launch/cell_layout.hpp"
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

// Containers and pods: every process alone at its address, hubs by name.
SwarmShape four_regions(bool lockstep = false) {
  SwarmShape s;
  s.regions = 4;
  s.uavs = 8;
  s.domain = 7;
  s.lockstep = lockstep;
  return s;
}

std::vector<std::string> names_of(const std::vector<bus::CellPeer>& peers) {
  std::vector<std::string> out;
  for (const auto& p : peers) {
    EXPECT_EQ(p.index, 0U) << p.address;  // every hub takes index 0 at its own address
    out.push_back(p.address);
  }
  return out;
}

TEST(NamedCells, EveryProcessNamesTheHubsItTalksToByTheTemplate) {
  const HubNames k8s{"place-{region}.pheromesh-swarm", "ground.pheromesh-swarm"};
  // UAV 6: home 6 % 4 = 2; its backup is a reserve in realtime, a peer in lockstep.
  const auto uav = named_cell(four_regions(), k8s, "uav", 6);
  EXPECT_FALSE(uav.index);
  EXPECT_EQ(names_of(uav.peers), std::vector<std::string>{"place-2.pheromesh-swarm"});
  ASSERT_EQ(uav.reserve.size(), 1U);
  EXPECT_NE(uav.reserve[0].address, "place-2.pheromesh-swarm");
  EXPECT_EQ(uav.domain, 7U);
  EXPECT_TRUE(uav.interface_address.empty());
  const auto lock = named_cell(four_regions(true), k8s, "uav", 6);
  EXPECT_EQ(lock.peers.size(), 2U);
  EXPECT_TRUE(lock.reserve.empty());
  // A place agent: index 0, the ground station and the other three.
  const auto place = named_cell(four_regions(), k8s, "place", 1);
  ASSERT_TRUE(place.index);
  EXPECT_EQ(*place.index, 0U);
  EXPECT_EQ(names_of(place.peers), (std::vector<std::string>{"ground.pheromesh-swarm", "place-0.pheromesh-swarm",
                                                             "place-2.pheromesh-swarm", "place-3.pheromesh-swarm"}));
  const auto ground = named_cell(four_regions(), HubNames{}, "ground", 0);
  EXPECT_EQ(names_of(ground.peers), (std::vector<std::string>{"place-0", "place-1", "place-2", "place-3"}));
  // A monitor: a member of every hub's cell.
  const auto monitor = named_cell(four_regions(), HubNames{}, "monitor", 0);
  EXPECT_FALSE(monitor.index);
  EXPECT_EQ(names_of(monitor.peers), (std::vector<std::string>{"ground", "place-0", "place-1", "place-2", "place-3"}));
}

TEST(NamedCells, TemplatesThatCannotNameEveryHubAreRefusedWithTheReason) {
  EXPECT_FALSE(check_hub_names(HubNames{}));
  EXPECT_EQ(hub_name(HubNames{"r{region}-{region}", "g"}, "place", 12), "r12-12");
  const auto no_region = check_hub_names(HubNames{"place", "ground"});
  ASSERT_TRUE(no_region);
  EXPECT_NE(no_region->find("has no {region}"), std::string::npos) << *no_region;
  const auto unknown = check_hub_names(HubNames{"place-{id}", "ground"});
  ASSERT_TRUE(unknown);
  EXPECT_NE(unknown->find("unknown placeholder at '{id}'"), std::string::npos) << *unknown;
  EXPECT_TRUE(check_hub_names(HubNames{"place-{region}", "ground-{region}"}));
  EXPECT_TRUE(check_hub_names(HubNames{"place-{region}", ""}));
}

TEST(NamedCells, NamesResolveToOneAddressEachAndTheProcessBindsItsRoute) {
  const std::map<std::string, std::vector<std::string>> dns{{"ground", {"10.88.0.2"}},
                                                            {"place-0", {"10.88.0.3"}},
                                                            {"place-1", {"10.88.0.4"}},
                                                            {"place-2", {"10.88.0.5"}},
                                                            {"place-3", {"10.88.0.6"}}};
  auto lookups = std::make_shared<int>(0);
  const NameResolver resolve =
      [&dns, lookups](const std::string& n) -> core::Result<std::optional<std::vector<std::string>>> {
    ++*lookups;
    auto it = dns.find(n);
    if (it == dns.end()) return std::optional<std::vector<std::string>>{};
    return std::optional<std::vector<std::string>>{it->second};
  };
  const auto route = [](const std::string& to) -> std::optional<std::string> {
    return to.rfind("10.88.", 0) == 0 ? std::optional<std::string>("10.88.0.9") : std::nullopt;
  };
  auto r = resolve_named_cell(named_cell(four_regions(), HubNames{}, "uav", 6), resolve, route);
  ASSERT_TRUE(r) << r.error().message;
  const auto& cell = std::get<bus::CellDiscovery>(r.value());
  EXPECT_EQ(bus::format_cell(cell), "peers=10.88.0.5:0;reserve=" + cell.reserve[0].address + ":0;iface=10.88.0.9");
  EXPECT_EQ(cell_environment("uav", cell),
            (std::vector<std::string>{"PHEROMESH_CELL=" + bus::format_cell(cell), "PHEROMESH_PARTICIPANT_ID=1"}));
  EXPECT_EQ(cell_environment("place", cell).size(), 1U);  // a hub's index is in its cell
  // The cell survives the round trip through its text.
  auto parsed = bus::parse_cell(bus::format_cell(cell), 7);
  ASSERT_TRUE(parsed) << parsed.error().message;
  EXPECT_EQ(parsed->peers[0].address, "10.88.0.5");
  // A place agent's names, each looked up once.
  *lookups = 0;
  ASSERT_TRUE(resolve_named_cell(named_cell(four_regions(), HubNames{}, "place", 0), resolve, route));
  EXPECT_EQ(*lookups, 4);
}

TEST(NamedCells, UnresolvedNamesAreListedAndSharedOrManyAddressesRefused) {
  std::map<std::string, std::vector<std::string>> dns{{"ground", {"10.88.0.2"}}, {"place-0", {"10.88.0.3"}}};
  const auto resolver = [&dns](const std::string& n) -> core::Result<std::optional<std::vector<std::string>>> {
    auto it = dns.find(n);
    if (it == dns.end()) return std::optional<std::vector<std::string>>{};
    return std::optional<std::vector<std::string>>{it->second};
  };
  const auto route = [](const std::string&) -> std::optional<std::string> { return "10.88.0.9"; };
  const auto ground = named_cell(four_regions(), HubNames{}, "ground", 0);
  auto waiting = resolve_named_cell(ground, resolver, route);
  ASSERT_TRUE(waiting);
  ASSERT_TRUE(std::holds_alternative<Unresolved>(waiting.value()));
  EXPECT_EQ(std::get<Unresolved>(waiting.value()).names, (std::vector<std::string>{"place-1", "place-2", "place-3"}));
  // Two hubs at one address would both take index 0 there.
  dns["place-1"] = {"10.88.0.3"};
  dns["place-2"] = {"10.88.0.5"};
  dns["place-3"] = {"10.88.0.6"};
  auto shared = resolve_named_cell(ground, resolver, route);
  ASSERT_FALSE(shared);
  EXPECT_NE(shared.error().message.find("'place-0' and 'place-1' resolve to the same address 10.88.0.3"),
            std::string::npos)
      << shared.error().message;
  // A name for several processes (a scaled service) is not one hub.
  dns["place-1"] = {"10.88.0.4", "10.88.0.7"};
  auto many = resolve_named_cell(ground, resolver, route);
  ASSERT_FALSE(many);
  EXPECT_NE(many.error().message.find("'place-1' resolves to 2 addresses"), std::string::npos) << many.error().message;
  // No route to the swarm.
  dns["place-1"] = {"10.88.0.4"};
  auto lost = resolve_named_cell(ground, resolver, [](const std::string&) { return std::optional<std::string>{}; });
  ASSERT_FALSE(lost);
  EXPECT_NE(lost.error().message.find("no route to 10.88.0.3"), std::string::npos) << lost.error().message;
}

TEST(CellLayout, APinnedUavFliesOnItsHostAndNamesItsGatewaysWhereTheyAre) {
  SwarmShape s = three_hosts();
  s.uav_hosts = {{5, 2}};  // UAV 5's home is place agent 1, on host 1
  const CellLayout l(s);
  EXPECT_EQ(l.host_of("uav", 5), 2U);
  EXPECT_EQ(l.host_of("uav", 1), 1U);  // not pinned: beside its home
  const auto c = l.cell_of("uav", 5);
  EXPECT_EQ(c.interface_address, "10.0.0.3");  // it binds its own host's address
  ASSERT_EQ(c.peers.size(), 1U);
  EXPECT_EQ(c.peers[0].address, "10.0.0.2");  // its home, on host 1
}

TEST(CellLayout, PinsAreParsedAndWhatCannotBeIsRefusedNamingTheItem) {
  auto pins = parse_uav_pins("0-2=1,7=0", 10, 3);
  ASSERT_TRUE(pins) << pins.error().message;
  EXPECT_EQ(pins.value(), (std::map<uint32_t, uint32_t>{{0, 1}, {1, 1}, {2, 1}, {7, 0}}));
  EXPECT_TRUE(parse_uav_pins("", 10, 1).value().empty());
  const std::pair<std::string, std::string> refused[] = {
      {"3=1", "this swarm has one host"},  // with hosts = 1 below
      {"3", "'3': no '='"},
      {"x=1", "the UAV ids are not numbers"},
      {"3=y", "the host is not a number"},
      {"5-2=1", "the range runs backwards"},
      {"9-10=1", "the swarm's UAVs are 0..9"},
      {"3=3", "the hosts are 0..2"},
      {"1-3=0,3=2", "UAV 3 is pinned twice"},
  };
  for (const auto& [text, why] : refused) {
    const auto r = parse_uav_pins(text, 10, text == "3=1" ? 1 : 3);
    ASSERT_FALSE(r) << text;
    EXPECT_NE(r.error().message.find(why), std::string::npos) << r.error().message;
  }
}

}  // namespace
}  // namespace pheromesh::cli
