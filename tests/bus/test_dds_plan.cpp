// `pheromesh run --dds`: which vendor each spawned process gets.
#include <gtest/gtest.h>

#include "launch/dds_plan.hpp"

using pheromesh::cli::DdsPlan;
using pheromesh::cli::parse_dds_plan;

namespace {
const std::vector<std::string> kVendors{"cyclone", "fastdds"};
}

TEST(DdsPlan, OneVendorForEveryProcess) {
  const auto p = parse_dds_plan("fastdds", kVendors);
  ASSERT_TRUE(static_cast<bool>(p));
  for (const char* role : {"ground", "place", "uav"}) {
    for (uint32_t i = 0; i < 4; ++i) EXPECT_EQ(p->vendor_of(role, i), "fastdds") << role << i;
  }
  EXPECT_TRUE(p->single_vendor());
  EXPECT_EQ(p->describe(), "fastdds");
}

TEST(DdsPlan, MixedAlternatesPlaceAgentsAndUavsTheOtherWayRound) {
  const auto p = parse_dds_plan("mixed", kVendors);
  ASSERT_TRUE(static_cast<bool>(p));
  EXPECT_EQ(p->vendor_of("ground", 0), "cyclone");
  EXPECT_EQ(p->vendor_of("place", 0), "cyclone");
  EXPECT_EQ(p->vendor_of("place", 1), "fastdds");
  EXPECT_EQ(p->vendor_of("place", 2), "cyclone");
  EXPECT_EQ(p->vendor_of("uav", 0), "fastdds");
  EXPECT_EQ(p->vendor_of("uav", 1), "cyclone");
  EXPECT_EQ(p->vendor_of("uav", 7), "cyclone");
  EXPECT_FALSE(p->single_vendor());
  EXPECT_EQ(p->describe(), "mixed (ground cyclone, place agents cyclone/fastdds, uavs fastdds/cyclone)");
}

TEST(DdsPlan, PerRoleVendorsAndCycloneForRolesLeftOut) {
  const auto p = parse_dds_plan("uav=fastdds,ground=fastdds", kVendors);
  ASSERT_TRUE(static_cast<bool>(p));
  EXPECT_EQ(p->vendor_of("ground", 0), "fastdds");
  EXPECT_EQ(p->vendor_of("place", 3), "cyclone");
  EXPECT_EQ(p->vendor_of("uav", 2), "fastdds");
  EXPECT_EQ(p->describe(), "mixed (ground fastdds, place agents cyclone, uavs fastdds)");
  const auto m = parse_dds_plan("place=mixed", kVendors);
  ASSERT_TRUE(static_cast<bool>(m));
  EXPECT_EQ(m->vendor_of("place", 1), "fastdds");
  EXPECT_EQ(m->vendor_of("uav", 0), "cyclone");
}

TEST(DdsPlan, ErrorsNameTheOptionAndWhatIsAllowed) {
  for (const char* bad : {"opendds", "uav=opendds", "tank=cyclone", "uav", "uav=cyclone,,place"}) {
    const auto p = parse_dds_plan(bad, kVendors);
    ASSERT_FALSE(static_cast<bool>(p)) << bad;
    EXPECT_EQ(p.error().message.rfind("--dds: ", 0), 0U) << p.error().message;
  }
  EXPECT_NE(parse_dds_plan("opendds", kVendors).error().message.find("cyclone, fastdds, mixed"), std::string::npos);
  EXPECT_NE(parse_dds_plan("tank=cyclone", kVendors).error().message.find("roles: ground, place, uav"), std::string::npos);
}
