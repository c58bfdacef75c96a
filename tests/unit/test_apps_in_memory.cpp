// The apps end to end on the in-memory bus (issue 43): the real place agents,
// UAVs and ground station (the lockstep conductor) of small-test, each app on
// its own thread and bus of one MemoryDomain, no DDS. Their lockstep run
// leaves the outputs core::Simulator leaves for the same scenario and seed,
// byte for byte, as the integration tests find for the processes over DDS
// (tests/integration/test_lockstep_faults.cpp). The apps run in a child
// process: the stop request that ends them is process-wide.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "ground_app.hpp"
#include "pheromesh/bus/memory.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/frontdoor/sim_outputs.hpp"
#include "pheromesh/runtime/process.hpp"
#include "place_app.hpp"
#include "uav_app.hpp"

namespace pheromesh {
namespace apps_in_memory_test {  // named: the unit tests build as one unity source

// small-test (30 x 30 cells, 2 x 2 regions, 4 UAVs, 3 targets), 30 ticks.
core::ScenarioConfig small_run() {
  auto loaded = core::load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto");
  EXPECT_TRUE(loaded.ok());
  core::ScenarioConfig s = loaded.value();
  s.ticks = 30;
  return s;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::unique_ptr<bus::Bus> bus_of(const std::shared_ptr<bus::MemoryDomain>& domain, const std::string& name) {
  bus::BusOptions o;
  o.process_name = name;
  return bus::make_memory_bus(domain, o);
}

// The swarm of `s` in lockstep, as `pheromesh run --clock lockstep` starts
// it: every place agent and UAV, and the ground station, which conducts and
// writes `out`. The launcher's end, too: once every UAV ended (on the
// conductor's Stop), the place agents and the ground station are stopped.
// The exit code: 0 if every app ended with 0, else 10 + the first app that
// did not (the ground station, then the UAVs, then the place agents).
int fly_swarm(const core::ScenarioConfig& s, const std::string& out) {
  spdlog::set_level(spdlog::level::warn);
  auto domain = bus::make_memory_domain();
  const uint32_t regions = s.geometry().region_count();
  std::vector<int> uav_rc(s.uavs, -1), place_rc(regions, -1);
  int ground_rc = -1;
  std::vector<std::thread> places, uavs;
  for (core::RegionId r = 0; r < regions; ++r) {
    places.emplace_back([&, r] {
      placeagent::PlaceConfig cfg;
      cfg.common.clock = "lockstep";
      cfg.region = r;
      if (placeagent::check_place_config(cfg, s)) return;
      placeagent::PlaceApp app(cfg, s, bus_of(domain, "place-" + std::to_string(r)));
      place_rc[r] = app.run();
    });
  }
  for (uint32_t u = 0; u < s.uavs; ++u) {
    uavs.emplace_back([&, u] {
      agent::UavConfig cfg;
      cfg.common.clock = "lockstep";
      cfg.id = u;
      agent::UavApp app(cfg, s, bus_of(domain, "uav-" + std::to_string(u)));
      uav_rc[u] = app.run();
    });
  }
  std::thread ground([&] {
    groundstation::GroundConfig cfg;
    cfg.common.clock = "lockstep";
    cfg.out_dir = out;
    cfg.progress_period_s = 3600;
    groundstation::GroundApp app(cfg, s, bus_of(domain, "ground"));
    ground_rc = app.run();
  });
  for (auto& t : uavs) t.join();
  runtime::request_shutdown();
  for (auto& t : places) t.join();
  ground.join();
  if (ground_rc != 0) return 10;
  for (uint32_t u = 0; u < s.uavs; ++u) {
    if (uav_rc[u] != 0) return static_cast<int>(11 + u);
  }
  for (core::RegionId r = 0; r < regions; ++r) {
    if (place_rc[r] != 0) return static_cast<int>(11 + s.uavs + r);
  }
  return 0;
}

// The simulator's outputs of `s` in `out`: its metrics.json as `pheromesh sim` writes them.
nlohmann::json simulate(const core::ScenarioConfig& s, const std::string& out) {
  core::Simulator sim(s);
  sim.run();
  EXPECT_EQ(frontdoor::write_sim_outputs(sim, out), "");
  return frontdoor::sim_metrics(sim, 1.0);
}

std::string fresh_dir(const std::string& name) {
  const auto dir =
      std::filesystem::path(testing::TempDir()) / ("pheromesh-apps-in-memory-" + std::to_string(getpid()) + "-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

TEST(AppsInMemory, ALockstepSwarmOfTheRealAppsOnTheInMemoryBusLeavesTheSimulatorsOutputsByteForByte) {
  const core::ScenarioConfig s = small_run();
  const std::string run_out = fresh_dir("lockstep");
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    alarm(240);  // a swarm that hangs fails the test (SIGALRM) rather than the suite's timeout
    _exit(fly_swarm(s, run_out));
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "the swarm did not end (signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0)
                                 << ")";
  ASSERT_EQ(WEXITSTATUS(status), 0) << "10: the ground station, 11..: a UAV, then a place agent (fly_swarm)";

  const std::string sim_out = fresh_dir("sim");
  const nlohmann::json sim = simulate(s, sim_out);
  const nlohmann::json run = nlohmann::json::parse(slurp(std::filesystem::path(run_out) / "metrics.json"));
  for (const char* key :
       {"ticks", "uavs", "coverage", "covered_cells", "targets_found", "acquisition_ticks", "revisit_response_ticks",
        "deposits_sent", "deposits_applied", "deposits_rejected", "field"}) {
    EXPECT_EQ(run[key], sim[key]) << key;
  }
  EXPECT_GT(run["deposits_applied"].get<uint64_t>(), 0U) << "a run that deposits nothing proves little";
  const std::string field = slurp(std::filesystem::path(run_out) / "final_field.txt");
  EXPECT_GT(field.size(), 1000U);
  for (const char* file : {"final_field.txt", "final_field.csv", "series.csv"}) {
    EXPECT_TRUE(slurp(std::filesystem::path(run_out) / file) == slurp(std::filesystem::path(sim_out) / file))
        << file << " differs from the simulator's";
  }

  // The guard: the same comparison tells another run apart (another seed).
  core::ScenarioConfig other = s;
  other.seed += 1;
  const std::string other_out = fresh_dir("sim-other-seed");
  (void)simulate(other, other_out);
  EXPECT_FALSE(slurp(std::filesystem::path(other_out) / "final_field.txt") == field);
  EXPECT_FALSE(slurp(std::filesystem::path(other_out) / "series.csv") ==
               slurp(std::filesystem::path(run_out) / "series.csv"));
  for (const auto& dir : {run_out, sim_out, other_out}) std::filesystem::remove_all(dir);
}

}  // namespace apps_in_memory_test
}  // namespace pheromesh
