// The per-process discovery configuration of a cell (bus/cell_discovery.hpp):
// the port arithmetic, its limits, and what each vendor's text says.
#include <gtest/gtest.h>

#include <string>

#include "pheromesh/bus/cell_discovery.hpp"

namespace pheromesh::bus {
namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

CellDiscovery hub(uint32_t domain, uint32_t index) {
  CellDiscovery c;
  c.domain = domain;
  c.index = index;
  return c;
}

CellDiscovery member_of(uint32_t domain, uint32_t hub_index) {
  CellDiscovery c;
  c.domain = domain;
  c.peers.push_back({"127.0.0.1", hub_index});
  return c;
}

TEST(CellDiscovery, PortsFollowTheStandardMappingOfBothVendors) {
  EXPECT_EQ(unicast_discovery_port(0, 0), 7410U);
  EXPECT_EQ(unicast_discovery_port(0, 1), 7412U);
  EXPECT_EQ(unicast_discovery_port(5, 3), 7400U + 1250U + 10U + 6U);
}

TEST(CellDiscovery, EveryIndexOfTheFirstHundredAndOneDomainsIsBelowTheEphemeralPorts) {
  for (uint32_t d = 0; d <= 100; ++d) {
    EXPECT_TRUE(check_cell(hub(d, kMaxParticipantIndex)).ok()) << "domain " << d;
  }
}

TEST(CellDiscovery, AHubWhosePortsReachTheEphemeralRangeIsRefused) {
  // Domain 101 starts at 32650: index 53 still fits (32766-32767), 54 not.
  EXPECT_TRUE(check_cell(hub(101, 53)).ok());
  const auto refused = check_cell(hub(101, 54));
  ASSERT_FALSE(refused.ok());
  EXPECT_TRUE(has(refused.error().message, "32768")) << refused.error().message;
  EXPECT_FALSE(check_cell(hub(102, 0)).ok());
}

TEST(CellDiscovery, IndicesAboveCyclonesLimitAndDomainsAbove232AreRefused) {
  EXPECT_FALSE(check_cell(hub(0, 120)).ok());
  EXPECT_FALSE(check_cell(member_of(0, 120)).ok());
  CellDiscovery d233 = member_of(0, 0);
  d233.domain = 233;
  EXPECT_FALSE(check_cell(d233).ok());
}

TEST(CellDiscovery, APeerMustBeAnIpv4Address) {
  CellDiscovery c = member_of(0, 0);
  c.peers[0].address = "place-0";
  EXPECT_FALSE(check_cell(c).ok());
  c.peers[0].address = "10.0.0.2";
  EXPECT_TRUE(check_cell(c).ok());
}

TEST(CellDiscovery, ACycloneMemberAnnouncesItselfOnlyToItsHubsPortWithoutMulticastOrIndex) {
  CellDiscovery c = member_of(3, 7);
  c.peers.push_back({"127.0.0.1", 8});  // the standby
  const std::string xml = cyclone_cell_config(c);
  EXPECT_TRUE(has(xml, "<AllowMulticast>false</AllowMulticast>"));
  EXPECT_TRUE(has(xml, "<ParticipantIndex>none</ParticipantIndex>"));
  EXPECT_TRUE(has(xml, "<Peers><Peer Address=\"127.0.0.1:8174\"/><Peer Address=\"127.0.0.1:8176\"/></Peers>"));
  EXPECT_FALSE(has(xml, "MaxAutoParticipantIndex"));
  EXPECT_TRUE(has(xml, "<GenerateKeyhash>true</GenerateKeyhash>"));  // mixed swarms need it
  EXPECT_TRUE(has(xml, "<SPDPInterval>5s</SPDPInterval>"));          // a hub started late is found soon
}

TEST(CellDiscovery, ACycloneCellOfALargeSwarmHeartbeatsEverySecondAndASmallOneKeepsCyclonesDefault) {
  const CellDiscovery c = member_of(3, 7);
  // Above 40 processes on the host (kQuietHeartbeatAbove, bus/src/dds_profiles.hpp).
  EXPECT_TRUE(has(cyclone_cell_config(c, 41), "<HeartbeatInterval>1s</HeartbeatInterval></Internal>"));
  EXPECT_TRUE(has(cyclone_cell_config(c, 500), "<HeartbeatInterval>1s</HeartbeatInterval></Internal>"));
  EXPECT_FALSE(has(cyclone_cell_config(c, 40), "HeartbeatInterval"));
  EXPECT_FALSE(has(cyclone_cell_config(c), "HeartbeatInterval")) << "not known: Cyclone's default";
}

TEST(CellDiscovery, ACycloneHubWithoutPeersNamesOnlyItselfSoCycloneAddsNoDefaultPeers) {
  const std::string xml = cyclone_cell_config(hub(3, 7));
  EXPECT_TRUE(has(xml, "<ParticipantIndex>7</ParticipantIndex>"));
  EXPECT_TRUE(has(xml, "<Peers><Peer Address=\"127.0.0.1:8174\"/></Peers>"));
}

TEST(CellDiscovery, ACycloneHubWithPeersNamesThemAndNotItself) {
  CellDiscovery c = hub(3, 7);
  c.peers.push_back({"127.0.0.1", 8});
  const std::string xml = cyclone_cell_config(c);
  EXPECT_TRUE(has(xml, "<Peers><Peer Address=\"127.0.0.1:8176\"/></Peers>"));
}

TEST(CellDiscovery, AFastDdsMemberHasOnlyUnicastMetatrafficAndItsHubsPortAsInitialPeer) {
  const FastDdsCellProfile p = fastdds_cell_profile(member_of(3, 7));
  EXPECT_TRUE(has(p.xml, "<participant profile_name=\"" + p.name + "\">"));
  EXPECT_TRUE(has(p.xml, "<initialPeersList><locator><udpv4><address>127.0.0.1</address><port>8174</port>"));
  EXPECT_TRUE(has(p.xml, "<metatrafficUnicastLocatorList>"));
  EXPECT_FALSE(has(p.xml, "<metatrafficMulticastLocatorList>"));
  EXPECT_TRUE(has(p.xml, "<useBuiltinTransports>false</useBuiltinTransports>"));
  EXPECT_FALSE(has(p.xml, "<participantID>"));
}

TEST(CellDiscovery, AFastDdsHubHasItsParticipantIdAndNoInitialPeers) {
  const FastDdsCellProfile p = fastdds_cell_profile(hub(3, 7));
  EXPECT_TRUE(has(p.xml, "<participantID>7</participantID>"));
  EXPECT_FALSE(has(p.xml, "<initialPeersList>"));
}

TEST(CellDiscovery, FastDdsProfilesOfDifferentCellsHaveDifferentNames) {
  // Fast DDS keeps a loaded profile (and transport) by name for the process.
  EXPECT_NE(fastdds_cell_profile(member_of(3, 7)).name, fastdds_cell_profile(member_of(3, 8)).name);
  EXPECT_NE(fastdds_cell_profile(hub(3, 7)).name, fastdds_cell_profile(hub(4, 7)).name);
  EXPECT_NE(fastdds_cell_profile(hub(3, 7)).name, fastdds_cell_profile(member_of(3, 7)).name);
}

}  // namespace
}  // namespace pheromesh::bus
