// The built-in Cyclone profiles as a process gets them (bus/src/dds_profiles).
#include <gtest/gtest.h>

#include <string>

#include "dds_profiles.hpp"

namespace pheromesh::bus {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(Profiles, ALargeOneHostSwarmAsksForAcknowledgementsEverySecondASmallOneEvery100Ms) {
  const std::string hb = "<HeartbeatInterval>1s</HeartbeatInterval>";
  for (const std::string profile : {"onehost", "onehost-unicast"}) {
    // Not known (a process started by hand) or small: Cyclone's 100 ms.
    EXPECT_EQ(count(cyclone_config(profile), "<HeartbeatInterval>"), 0U) << profile;
    EXPECT_EQ(count(cyclone_config(profile, {}, kQuietHeartbeatAbove), "<HeartbeatInterval>"), 0U) << profile;
    // One more process: 1 s, once, inside <Internal>.
    const std::string large = cyclone_config(profile, {}, kQuietHeartbeatAbove + 1);
    ASSERT_EQ(count(large, hb), 1U) << profile;
    const std::size_t at = large.find(hb);
    EXPECT_LT(large.rfind("<Internal>", at), at) << profile;
    EXPECT_EQ(large.find("</Internal>", at), at + hb.size()) << profile;
  }
  // The LAN and namespace profiles spread a swarm over hosts: unchanged.
  EXPECT_EQ(cyclone_config("netns", {}, 500), cyclone_config("netns"));
  EXPECT_EQ(cyclone_config("lan", {}, 500), cyclone_config("lan"));
  EXPECT_EQ(cyclone_heartbeat(kQuietHeartbeatAbove + 1), "1s");
  EXPECT_EQ(cyclone_heartbeat(0), "");
}

TEST(DdsProfiles, AFastDdsWriterOfALargeSwarmHeartbeatsEverySecondWithoutPiggybackingAndASmallOneEvery100ms) {
  using std::chrono::milliseconds;
  const FastDdsWriterPace quiet = fastdds_writer_pace(kQuietHeartbeatAbove + 1);
  EXPECT_EQ(quiet.heartbeat, milliseconds(1000));
  EXPECT_FALSE(quiet.piggyback);
  EXPECT_EQ(fastdds_writer_pace(500), quiet);
  // A small swarm and an unknown size: every 100 ms and with every write.
  const FastDdsWriterPace prompt{milliseconds(100), true};
  EXPECT_EQ(fastdds_writer_pace(kQuietHeartbeatAbove), prompt);
  EXPECT_EQ(fastdds_writer_pace(0), prompt);
}

}  // namespace
}  // namespace pheromesh::bus
