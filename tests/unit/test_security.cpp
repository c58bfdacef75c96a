// DDS Security material without DDS: the role grants (bus/security.hpp) and
// the OpenSSL PKI (auth/pki.hpp). The processes that enforce them are in
// tests/integration/test_security.cpp.
#include <gtest/gtest.h>

#include <algorithm>

#include "pheromesh/auth/pki.hpp"
#include "pheromesh/bus/security.hpp"

using namespace pheromesh;  // NOLINT

namespace {

bool allows(const std::vector<bus::TopicRule>& rules, const std::string& topic, const std::string& partition) {
  return std::any_of(rules.begin(), rules.end(), [&](const bus::TopicRule& r) {
    return r.topic == topic && std::find(r.partitions.begin(), r.partitions.end(), partition) != r.partitions.end();
  });
}

bool names_topic(const std::vector<bus::TopicRule>& rules, const std::string& topic) {
  return std::any_of(rules.begin(), rules.end(), [&](const bus::TopicRule& r) { return r.topic == topic; });
}

}  // namespace

TEST(SecurityGrants, AUavWritesOnlyItsOwnStateToItsHomeAndNeverDepositsTilesClockOrCommands) {
  const bus::SwarmShape shape{10, 4, 0, 0};
  const auto g = bus::grant_for("uav-6", shape);  // home region 6 mod 4 = 2
  ASSERT_TRUE(g.ok()) << g.error().message;
  EXPECT_EQ(g->subject, "CN=uav-6");
  EXPECT_TRUE(allows(g->publish, "pheromesh_uav_state", "s.2"));
  EXPECT_FALSE(allows(g->publish, "pheromesh_uav_state", "s.*"));
  // Its deposits go up in its states (UavStateMsg::deposits): no deposit writer.
  for (const char* t : {"pheromesh_deposit", "pheromesh_tile", "pheromesh_clock", "pheromesh_command", "pheromesh_region_field",
                        "pheromesh_view", "pheromesh_halo"}) {
    EXPECT_FALSE(names_topic(g->publish, t)) << t;
  }
  EXPECT_TRUE(allows(g->subscribe, "pheromesh_view", "u.6"));
  // The lockstep tree: its reports go to its home (2) or backup (3) place
  // agent only, and it hears the clock only as they relay it.
  EXPECT_TRUE(allows(g->publish, "pheromesh_phase_done", "d.2"));
  EXPECT_TRUE(allows(g->publish, "pheromesh_phase_done", "d.3"));
  EXPECT_FALSE(allows(g->publish, "pheromesh_phase_done", "c"));
  // Relays: it writes nothing the ground station or the swarm reads
  // directly; its detections and broadcasts go up to its gateways, it hears
  // broadcasts and commands as they relay them.
  EXPECT_TRUE(allows(g->publish, "pheromesh_detection", "g.2"));
  EXPECT_TRUE(allows(g->publish, "pheromesh_detection", "g.3"));
  EXPECT_FALSE(allows(g->publish, "pheromesh_detection", "g"));
  EXPECT_TRUE(allows(g->publish, "pheromesh_broadcast", "bu.2"));
  EXPECT_FALSE(allows(g->publish, "pheromesh_broadcast", "b"));
  EXPECT_FALSE(names_topic(g->publish, "pheromesh_uav_state_ground"));
  EXPECT_TRUE(allows(g->subscribe, "pheromesh_broadcast", "bd.3"));
  EXPECT_FALSE(allows(g->subscribe, "pheromesh_broadcast", "b"));
  EXPECT_TRUE(allows(g->subscribe, "pheromesh_command", "k.2"));
  EXPECT_FALSE(allows(g->subscribe, "pheromesh_command", "k"));
  EXPECT_FALSE(allows(g->publish, "pheromesh_phase_done", "d.1"));
  EXPECT_TRUE(allows(g->subscribe, "pheromesh_clock_relay", "c.2"));
  EXPECT_TRUE(allows(g->subscribe, "pheromesh_clock_relay", "cb.3")) << "as its backup relays it";
  EXPECT_FALSE(allows(g->subscribe, "pheromesh_clock_relay", "c.3")) << "to the UAVs homed on 3";
  EXPECT_FALSE(names_topic(g->subscribe, "pheromesh_clock"));
}

TEST(SecurityGrants, OnlyTheGroundStationWritesTheClockAPlaceAgentRelaysItToItsOwnUavsAndTheMonitorWritesNothing) {
  const bus::SwarmShape shape{3, 2, 1, 0};
  for (const auto& g : bus::swarm_grants(shape)) {
    const bool ground = g.name == "ground";
    const bool place = g.name.rfind("place-", 0) == 0;
    // The conductor's clock is a topic of its own: permissions need no
    // partition to keep everyone else from writing it (Fast DDS 2.9 checks none).
    EXPECT_EQ(names_topic(g.publish, "pheromesh_clock"), ground) << g.name;
    EXPECT_EQ(names_topic(g.publish, "pheromesh_clock_relay"), place) << g.name;
    if (place) {
      const std::string region = g.name.substr(6, 1);  // place-R, place-R.rN (R < 10 here)
      EXPECT_TRUE(allows(g.publish, "pheromesh_clock_relay", "c." + region)) << g.name;
      EXPECT_TRUE(allows(g.publish, "pheromesh_clock_relay", "cb." + region)) << g.name;
      EXPECT_FALSE(allows(g.publish, "pheromesh_clock_relay", "cb." + std::string(region == "0" ? "1" : "0")))
          << g.name;
      EXPECT_TRUE(allows(g.subscribe, "pheromesh_phase_done", "d." + region)) << g.name;
      EXPECT_FALSE(allows(g.publish, "pheromesh_clock_relay", "c." + std::string(region == "0" ? "1" : "0")))
          << g.name;
    }
    // Commands: the ground station writes them to the place agents ("k"),
    // each place agent relays them to its own UAVs only.
    EXPECT_EQ(allows(g.publish, "pheromesh_command", "k"), ground) << g.name;
    EXPECT_EQ(names_topic(g.publish, "pheromesh_command"), ground || place) << g.name;
    EXPECT_EQ(names_topic(g.publish, "pheromesh_uav_state_ground"), place) << g.name;
    if (place) {
      const std::string region = g.name.substr(6, 1);
      EXPECT_TRUE(allows(g.publish, "pheromesh_command", "k." + region)) << g.name;
      EXPECT_FALSE(allows(g.publish, "pheromesh_command", "k." + std::string(region == "0" ? "1" : "0"))) << g.name;
      EXPECT_TRUE(allows(g.publish, "pheromesh_uav_state_ground", "g")) << g.name;
    }
    if (g.name == bus::kMonitorIdentity) {
      EXPECT_TRUE(g.publish.empty());
    }
  }
  EXPECT_EQ(bus::swarm_grants(shape).size(), 2U * 2 + 3 + 2);  // places and standbys, UAVs, ground, monitor
  EXPECT_TRUE(bus::grant_for("place-1.r1", shape).ok());
  EXPECT_FALSE(bus::grant_for("place-1.r2", shape).ok());
  EXPECT_FALSE(bus::grant_for("uav-3", shape).ok());
  EXPECT_FALSE(bus::grant_for("probe-0", shape).ok());
}

TEST(SecurityDocuments, PermissionsDenyByDefaultAndTheGovernanceFollowsTheProtection) {
  const auto g = bus::grant_for("place-0", {1, 1, 0, 0}).value();
  const std::string p = bus::permissions_xml(g, "2026-01-01T00:00:00", "2027-01-01T00:00:00");
  EXPECT_NE(p.find("<subject_name>CN=place-0</subject_name>"), std::string::npos);
  EXPECT_NE(p.find("<default>DENY</default>"), std::string::npos);
  EXPECT_NE(p.find("<partition>h.0.*</partition>"), std::string::npos);  // its rings, to any neighbour
  EXPECT_NE(p.find("<partition>h.*.0</partition>"), std::string::npos);  // its neighbours' rings, to it
  EXPECT_NE(bus::governance_xml(bus::Protection::Encrypt).find("<data_protection_kind>ENCRYPT"), std::string::npos);
  EXPECT_NE(bus::governance_xml(bus::Protection::Sign).find("<data_protection_kind>SIGN"), std::string::npos);
  EXPECT_NE(bus::governance_xml(bus::Protection::None).find("<data_protection_kind>NONE"), std::string::npos);
  EXPECT_NE(bus::governance_xml(bus::Protection::None).find("<allow_unauthenticated_participants>false"),
            std::string::npos);
  EXPECT_FALSE(bus::parse_protection("rot13").ok());
}

TEST(SecurityPki, ASignedDocumentVerifiesAgainstItsCaAndATamperedOneDoesNot) {
  const auto v = auth::validity_from_now(2);
  const auto ca = auth::make_ca("test CA", v);
  ASSERT_TRUE(ca.ok()) << ca.error().message;
  const auto id = auth::make_identity(ca.value(), "uav-0", v);
  ASSERT_TRUE(id.ok()) << id.error().message;
  EXPECT_NE(id->key.find("PRIVATE KEY"), std::string::npos);
  const std::string doc = "<dds><permissions/></dds>\n";
  const auto signed_doc = auth::smime_sign(ca.value(), doc);
  ASSERT_TRUE(signed_doc.ok()) << signed_doc.error().message;
  std::string content;
  EXPECT_TRUE(auth::smime_verify(ca->cert, signed_doc.value(), &content));
  EXPECT_NE(content.find("<permissions/>"), std::string::npos);
  // The guard: one changed byte of the document, or another CA, fails.
  std::string tampered = signed_doc.value();
  tampered.replace(tampered.find("<permissions/>"), 14, "<permissionz/>");
  EXPECT_FALSE(auth::smime_verify(ca->cert, tampered));
  const auto other = auth::make_ca("other CA", v);
  ASSERT_TRUE(other.ok());
  EXPECT_FALSE(auth::smime_verify(other->cert, signed_doc.value()));
}

namespace pheromesh::bus {
namespace {

TEST(SecurityProfiles, FastDdsSecureNeedsUnicastDiscoveryAndCycloneTakesAnyProfile) {
  for (const char* flat : {"onehost", "netns", "lan"}) {
    const auto e = check_secure_profile("fastdds", flat, /*cell=*/false);
    ASSERT_TRUE(e.has_value()) << flat;
    EXPECT_NE(e->find(std::string("not ") + flat + ":"), std::string::npos) << *e;
    EXPECT_NE(e->find("cells (the default), onehost-unicast or lan-unicast"), std::string::npos) << *e;
    EXPECT_FALSE(check_secure_profile("cyclone", flat, false).has_value()) << flat;
    EXPECT_FALSE(check_secure_profile("fastdds", flat, /*cell=*/true).has_value()) << "a cell: one unicast socket";
  }
  for (const char* unicast : {"cells", "onehost-unicast", "lan-unicast", "/etc/my-fastdds.xml"}) {
    EXPECT_FALSE(check_secure_profile("fastdds", unicast, false).has_value()) << unicast;
  }
}

}  // namespace
}  // namespace pheromesh::bus
