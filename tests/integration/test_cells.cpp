// Cells (issue 25; docs/dds.md, "Cell discovery"; docs/architecture.md,
// "Relays"): with `pheromesh run --dds-profile cells` every process
// announces itself only to the processes it talks to - a UAV to its gateway
// place agents, which relay everything else it sends and receives. Domains
// 56-57.
#include <regex>

#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers
using nlohmann::json;

TEST(Cells, ALockstepSwarmInCellsGivesTheSimulatorsNumbersWithBroadcastsRelayed) {
  // Shostak: the UAVs' "target found" broadcasts travel UAV -> gateway ->
  // every place agent -> every UAV, the clock and the reports through the
  // tree, states and detections to the ground station through the gateways.
  expect_lockstep_matches_sim("shostak-small.textproto", "", 56, "cells-shostak", "--dds-profile cells");
}

TEST(Cells, AProcessThatNamesOnePlaceAgentHearsOnlyThatOneWhileTheSwarmFlies) {
  const std::string out = out_dir("cells-realtime");
  // No profile flag: cells are the default. 12 s of flight: a Fast DDS
  // monitor has found the run only 5 s after its start (twice, fresh clones
  // of stops 45 and 46), and a 6 s flight then ended as it attached.
  const Background swarm = start_run("small-test.textproto", out, 57, "--uavs 4 --duration 12");
  ASSERT_TRUE(wait_for_text(swarm.out_path, "places 4/4", std::chrono::seconds(30))) << slurp(swarm.out_path);
  // A monitor attaches with the command the run printed: it names every hub
  // (and on Fast DDS takes the domain's highest participant id, past every
  // hub's and UAV's). It starts before the probe: started after it, it once
  // attached as the swarm ended and heard no place agent before they did
  // (fresh clone, Fast DDS).
  std::smatch hint;
  const std::string printed = slurp(swarm.out_path);
  ASSERT_NE(printed.find("profile cells"), std::string::npos) << printed;
  ASSERT_TRUE(std::regex_search(printed, hint,
                                std::regex("watch it with: (pheromesh attach --domain 57 --cell-hubs ([0-9]+))")))
      << printed;
  EXPECT_EQ(hint[2], "5");  // the ground station and 4 place agents
  const std::string mon = out_dir("cells-attach");
  const Background monitor =
      start({"/bin/sh", "-c", kBin + "/" + hint[1].str() + " --timeout 20 --out " + mon + " 2>&1"}, mon + ".txt");
  // A member naming place agent 0 only (hub index 1; the ground station is
  // hub 0): it hears its health and its own, none of the other three place
  // agents', which never learn of it. As a Fast DDS participant it needs an
  // id of its own past the hubs' (0-4), not the UAVs' (120-123): without one Fast
  // DDS takes the first free index, can bind a hub's port beside it and then
  // receives what the other hubs send that hub (docs/dds.md). 5 s: on a
  // loaded host 3 s were not always enough to discover the hub (the swarm
  // flies 12 s; the probe ends as soon as it heard both).
  const Output p =
      run(kBin +
          "/pheromesh-test-probe --domain 57 --participant-id 40 --cell-peer 1 discover --id 900 --expect 2 "
          "--timeout 5");
  EXPECT_EQ(p.exit_code, 0) << p.text;
  EXPECT_NE(p.text.find("heard: 0,900\n"), std::string::npos) << p.text;
  ASSERT_EQ(wait_exit(swarm.pid, std::chrono::seconds(120)), 0) << slurp(swarm.out_path);
  ASSERT_EQ(wait_exit(monitor.pid, std::chrono::seconds(60)), 0) << slurp(monitor.out_path);
  const json seen = read_metrics(mon);
  ASSERT_FALSE(seen.is_null()) << slurp(monitor.out_path);
  EXPECT_EQ(seen["uavs"], 4) << slurp(monitor.out_path);  // every UAV's state, relayed by the place agents
  expect_accounting(seen);
  const json m = read_metrics(out);
  ASSERT_FALSE(m.is_null()) << slurp(swarm.out_path);
  EXPECT_EQ(m["place_agents_finished"], 4);
  EXPECT_EQ(m["processes_crashed"], 0);
  EXPECT_GT(m["coverage"].get<double>(), 0.2);
  // Every UAV's state reached the ground station through its gateway.
  ASSERT_EQ(m["uav_status"].size(), 4U) << m.dump(2);
  for (const auto& [id, u] : m["uav_status"].items()) EXPECT_GT(u["last_tick"].get<uint32_t>(), 10U) << "uav " << id;
  expect_accounting(m);
}
