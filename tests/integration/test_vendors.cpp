// Swarms whose roles run on different DDS vendors, set per role with
// `pheromesh run --dds ROLE=VENDOR,...` (independent of PHEROMESH_DDS, so
// these run once). Domains 36-37.
#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers

namespace {

// Every process log says which vendor it runs on: "... over <vendor>".
void expect_vendor(const std::string& out, const std::string& process, const std::string& vendor) {
  const std::string log = slurp(out + "/logs/" + process + ".log");
  EXPECT_NE(log.find("over " + vendor), std::string::npos) << process << " is not on " << vendor << ":\n" << log;
}

}  // namespace

TEST(Vendors, CyclonePlaceAgentsServeFastDdsUavsAndTheReverseWithTheSimulatorsNumbers) {
  expect_lockstep_matches_sim("small-test.textproto", "--ticks 100", 36, "vendors-cyclone-places",
                              "--dds ground=cyclone,place=cyclone,uav=fastdds");
  expect_lockstep_matches_sim("small-test.textproto", "--ticks 100", 36, "vendors-fastdds-places",
                              "--dds ground=fastdds,place=fastdds,uav=cyclone");
}

TEST(Vendors, RunsSayWhichVendorEachProcessUses) {
  const std::string out = out_dir("vendors-mixed-plan");
  const Output o = run(pheromesh_run("small-test.textproto", out, 36, "--clock lockstep --ticks 5 --dds mixed"));
  ASSERT_EQ(o.exit_code, 0) << o.text;
  expect_vendor(out, "place-0", "cyclone");
  expect_vendor(out, "place-1", "fastdds");
  expect_vendor(out, "uav-0", "fastdds");
  expect_vendor(out, "uav-1", "cyclone");
  const json m = read_metrics(out);
  EXPECT_EQ(m["dds"], "mixed (ground cyclone, place agents cyclone/fastdds, uavs fastdds/cyclone)");
  for (const auto& p : m["processes"]) {
    if (p["name"] == "uav-2" || p["name"] == "place-3") {
      EXPECT_EQ(p["dds"], "fastdds") << p.dump();
    }
  }
  const Output bad = run(kBin + "/pheromesh run " + kSrc + "/scenarios/small-test.textproto --dds uav=opendds --out " + out);
  EXPECT_EQ(bad.exit_code, 2) << bad.text;
  EXPECT_NE(bad.text.find("--dds: unknown vendor 'opendds'"), std::string::npos) << bad.text;
  const Output one = run(kBin + "/pheromesh-uav --scenario " + kSrc + "/scenarios/small-test.textproto --id 0 --dds mixed");
  EXPECT_EQ(one.exit_code, 3) << one.text;
  EXPECT_NE(one.text.find("is for pheromesh run"), std::string::npos) << one.text;
}

TEST(Vendors, EachVendorNoticesAKilledProcessOfTheOtherThroughLiveliness) {
  // Each watcher on one vendor, what it watches on the other: the place
  // agents watch their UAVs' state writers (and relay a departure to the
  // ground station), the ground station watches the place agents' health
  // writers. A UAV and a place agent (not the UAV's home, which reports
  // it) are killed with SIGKILL (no goodbye on the wire).
  for (const std::string plan : {"ground=fastdds,place=cyclone,uav=fastdds", "ground=cyclone,place=fastdds,uav=cyclone"}) {
    const std::string out = out_dir("vendors-liveliness-" + plan.substr(7, plan.find(',') - 7));
    const Output o = run(pheromesh_run("small-test.textproto", out, 37,
                                       "--uavs 3 --ticks 150 --rate 25 --kill \"uav:1@3s,place:3@4s\" --dds " + plan));
    ASSERT_EQ(o.exit_code, 0) << plan << "\n" << o.text;
    const json m = read_metrics(out);
    EXPECT_EQ(m["processes_killed"], 2) << plan;
    EXPECT_EQ(m["processes_crashed"], 0) << plan;
    EXPECT_NE(o.text.find("uav 1 lost (liveliness)"), std::string::npos) << plan << "\n" << o.text;
    EXPECT_NE(o.text.find("place agent 3 lost (liveliness)"), std::string::npos) << plan << "\n" << o.text;
    // The survivors flew the whole run.
    for (const char* id : {"0", "2"}) EXPECT_EQ(m["uav_status"][id]["last_tick"], 150) << plan << " uav " << id;
  }
}
