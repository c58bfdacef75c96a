// Forged samples from a real process on an open domain (issue 16, deliverable
// 2; docs/architecture.md "What a receiver refuses"): pheromesh-test-probe
// forge writes each attack of the issue into a running swarm - a phantom
// target mark from a UAV that does not exist, the sequence number 2^32-1
// under a real UAV's id, tiles, field chunks and a halo with 1e30 or a tick
// far ahead, states and detections that would move coverage and "targets
// found", a lockstep clock Stop - and the run must not notice, while every
// refusal is counted per reason in metrics.json. Domains 80-81 (and 82-83:
// issue 42, at the end).
#include <regex>
#include <sstream>

#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers
using nlohmann::json;

namespace {

// foreign_writer is asserted per receiver below: the forger's state of
// UAV 1 reaches UAV 1's home, which in some runs takes UAV 1's own next
// state first (WriterLatch.* test the latch); its deposits into UAV 0's home
// and its tiles and field chunks for the ground station are refused for the
// process that wrote them (issue 28).
const char* const kReasons[] = {"unknown_uav",        "seq_far_ahead", "tick_far_ahead",
                                "value_out_of_range", "foreign_clock", "implausible_detection",
                                "implausible_state",  "unknown_place", "refused_state_deposit"};

// The forger writes once every receiver matched its writers, then stays
// until it is ended after the swarm (its writers' instances outlive every
// take); end_forger returns what it printed once it exited 0.
using Forger = Background;
Forger start_forger(int domain, bool lockstep, const std::string& name) {
  std::vector<std::string> args{kBin + "/pheromesh-test-probe",
                                "--domain",
                                std::to_string(domain),
                                "forge",
                                "--scenario",
                                kSrc + "/scenarios/small-test.textproto",
                                "--uavs",
                                "2"};
  if (lockstep) args.emplace_back("--lockstep");
  return start(args, out_path(name));
}
std::string end_forger(const Forger& f) {
  kill(f.pid, SIGTERM);
  const int code = wait_exit(f.pid, std::chrono::seconds(30));
  std::string text = slurp(f.out_path);
  EXPECT_EQ(code, 0) << text;
  return text;
}

void expect_refused(const json& m, const char* reason) {
  ASSERT_TRUE(m["refused"].contains(reason)) << m["refused"].dump();
  EXPECT_GT(m["refused"][reason].get<uint64_t>(), 0U) << reason << "\n" << m["refused_by"].dump(2);
}

// Issue 42 D4-D5, in either clock: the healths of a standby the swarm does
// not have and of a region beyond the map's, refused at the ground station
// (their counters replace nobody's); in realtime the served-UAVs chunk of a
// standby it does not have, at the 3 other place agents (a lockstep place
// agent reads no served-UAVs chunk: the place clock lists them); the 3
// deposits of UAV 0 the stranger's state carried, refused with it by the
// place agent it reached (never forwarded to region 0 in that place agent's
// name).
void expect_issue42_refusals(const json& m, bool lockstep) {
  EXPECT_EQ(m["refused_by"]["ground"]["unknown_place"], 2) << m["refused_by"].dump(2);
  EXPECT_EQ(m["refused_by"]["places"]["unknown_place"], lockstep ? 0 : 3) << m["refused_by"].dump(2);
  EXPECT_EQ(m["refused_by"]["places"]["refused_state_deposit"], 3) << m["refused_by"].dump(2);
  EXPECT_EQ(m["place_agents"], 4) << "no place agent of an id the run does not have";
  for (const auto& [name, p] : m["place_replicas"].items()) {
    EXPECT_EQ(p["replica"], 0) << "no standby's counters: " << name;
  }
}

}  // namespace

TEST(Plausibility, ForgedSamplesLeaveALockstepRunTheSimulatorsAndEachIsRefusedAndCounted) {
  // Long enough (about 3 ms a tick) that the forger, which starts once the
  // clock is at tick 5 and must have its writers discovered, forges while
  // every process still takes clocks - last the UAV state it waits to have
  // matched (with 2000 ticks a run now and then ended before it).
  const std::string args = "--uavs 2 --ticks 4000 --seed 3";
  const std::string run_out = out_dir("plaus-lockstep");
  const std::string sim_out = out_dir("plaus-sim");
  // The forger speaks flat discovery: the swarm flies in the flat profile.
  const Background swarm =
      start_run("small-test.textproto", run_out, 80, "--clock lockstep --dds-profile onehost " + args);
  const Forger f = start_forger(80, true, "forge-lockstep");
  // 3 deposits (the next ten of UAV 0 counted once), 2 tiles, 3 field
  // chunks, 2 tile chunks and a served-UAVs chunk for the place agents, 1
  // halo, 3 states and one of UAV 1 from the forger's own writer, 2
  // detections, 1 clock to the place agents and 4 as relayed to each
  // region's UAVs; issue 42: 2 healths of place agents the run does not
  // have, 2 served-UAVs chunks naming UAV 0, a forwarded deposit of the
  // tick before and 3 lockstep reports.
  // The forged Stop did not end the run: it finishes every tick, exit 0.
  ASSERT_EQ(wait_exit(swarm.pid, std::chrono::seconds(300)), 0) << slurp(swarm.out_path);
  const std::string forged = end_forger(f);
  EXPECT_NE(forged.find("forged 31 samples"), std::string::npos) << forged;
  EXPECT_EQ(forged.find("not matched"), std::string::npos) << forged;
  const Output s =
      run(kBin + "/pheromesh sim " + kSrc + "/scenarios/small-test.textproto --quiet --out " + sim_out + " " + args);
  ASSERT_EQ(s.exit_code, 0) << s.text;
  const json a = read_metrics(run_out);
  const json b = read_metrics(sim_out);
  ASSERT_FALSE(a.is_null()) << slurp(swarm.out_path);
  // Exactly the simulator's run: no coverage, target, deposit or field value
  // of the forger's got in.
  for (const char* key : {"ticks", "uavs", "coverage", "covered_cells", "targets_found", "acquisition_ticks",
                          "revisit_response_ticks", "deposits_sent", "deposits_applied", "field"}) {
    EXPECT_EQ(a[key], b[key]) << key;
  }
  for (const auto& [id, u] : b["uav_status"].items()) {
    for (const char* key : {"x", "y", "last_tick"})
      EXPECT_EQ(a["uav_status"][id][key], u[key]) << "uav " << id << " " << key;
  }
  const std::string field = slurp(run_out + "/final_field.txt");
  EXPECT_GT(field.size(), 1000U);
  EXPECT_TRUE(field == slurp(sim_out + "/final_field.txt")) << "final pheromone fields differ";
  EXPECT_EQ(field.find("e+30"), std::string::npos);
  // UAV 0 kept delivering after the forged 2^32-1 and the forged next ten:
  // every deposit the UAVs sent was applied; the phantom mark and the 2^32-1
  // were rejected, and the ten refused for their writer (below).
  EXPECT_EQ(a["deposits_applied"], a["deposits_sent"]);
  EXPECT_EQ(a["deposits_rejected"], 2) << a.dump(2);
  EXPECT_EQ(a["deposits_lost"], 0);
  EXPECT_EQ(a["uavs"], 2);  // the forger's UAV id is nobody's status
  for (const char* reason : kReasons) expect_refused(a, reason);
  // Who refused what: the clock by UAVs and place agents, the deposits by
  // place agents 0 and 1, the detection of UAV 0 by place agent 3 (which is
  // not its gateway), the ground station's tiles and chunks by the ground.
  EXPECT_GE(a["refused_by"]["uavs"]["foreign_clock"].get<uint64_t>(), 2U);
  EXPECT_GE(a["refused_by"]["places"]["foreign_clock"].get<uint64_t>(), 4U);
  EXPECT_EQ(a["refused_by"]["places"]["seq_far_ahead"], 1);
  // UAV 0's next ten deposits, forwarded to its own gateway, which takes
  // them from its states only; and the state of UAV 1 from the forger's
  // writer, if its home took it before UAV 1's next one replaced it.
  // (The forger's served-UAVs chunks as region 0's reach no lockstep place
  // agent: the place clock lists the served UAVs.)
  EXPECT_GE(a["refused_by"]["places"]["foreign_writer"].get<uint64_t>(), 10U) << a["refused_by"].dump(2);
  EXPECT_LE(a["refused_by"]["places"]["foreign_writer"].get<uint64_t>(), 18U) << a["refused_by"].dump(2);
  EXPECT_EQ(a["refused_by"]["places"]["implausible_detection"], 1);
  EXPECT_GT(a["refused_by"]["ground"]["foreign_writer"].get<uint64_t>(), 0U) << a["refused_by"].dump(2);
  EXPECT_EQ(b["refused"]["unknown_uav"], 0);  // the simulator's honest swarm refuses nothing
  expect_issue42_refusals(a, /*lockstep=*/true);
  // Lockstep only: the forwarded deposit of the tick before, at region 1;
  // UAV 0's report into its home's partition, from another process; its
  // report and place agent 0's straight to the conductor. A report is kept
  // last-1 per reporting process: the real one of the next phase may
  // replace a forged one before it is taken (never taken, so not counted
  // either; the field above says none was taken).
  EXPECT_EQ(a["refused_by"]["places"]["unannounced_deposit"], 1) << a["refused_by"].dump(2);
  EXPECT_LE(a["refused_by"]["places"]["foreign_report"].get<uint64_t>(), 1U) << a["refused_by"].dump(2);
  EXPECT_GE(a["refused_by"]["ground"]["foreign_report"].get<uint64_t>(), 1U) << a["refused_by"].dump(2);
  EXPECT_LE(a["refused_by"]["ground"]["foreign_report"].get<uint64_t>(), 2U) << a["refused_by"].dump(2);
  EXPECT_EQ(a["deposits_lost"], 0);
}

TEST(Plausibility, ForgedSamplesInARealtimeRunAreRefusedAndTheAttackedUavKeepsDelivering) {
  const std::string out = out_dir("plaus-realtime");
  // 12 s: the forger, once every receiver matched its writers, waits for a
  // state of the UAV it impersonates, which must still be flying when
  // the forged state arrives (a UAV silent for a lease may be taken over:
  // a restarted one).
  const Background swarm =
      start_run("small-test.textproto", out, 81, "--uavs 2 --ticks 300 --rate 25 --dds-profile onehost");
  const Forger f = start_forger(81, false, "forge-realtime");
  ASSERT_EQ(wait_exit(swarm.pid, std::chrono::seconds(120)), 0) << slurp(swarm.out_path);
  const std::string forged = end_forger(f);
  // Issue 42: 2 healths, 2 served-UAVs chunks, a forwarded deposit (no
  // lockstep reports in realtime).
  EXPECT_NE(forged.find("forged 28 samples"), std::string::npos) << forged;
  const json m = read_metrics(out);
  ASSERT_FALSE(m.is_null()) << slurp(swarm.out_path);
  EXPECT_EQ(m["processes_crashed"], 0);
  EXPECT_EQ(m["uavs"], 2);
  for (const char* id : {"0", "1"}) EXPECT_EQ(m["uav_status"][id]["last_tick"], 300) << id;
  EXPECT_EQ(m["deposits_applied"], m["deposits_sent"]);
  // The phantom mark and the 2^32-1 refused for what they say; UAV 0's
  // plausible next ten for the process that forwarded them (below).
  EXPECT_EQ(m["deposits_rejected"], 2) << m.dump(2);
  EXPECT_EQ(m["deposits_unconfirmed_by_uavs"], 0);
  EXPECT_EQ(slurp(out + "/final_field.txt").find("e+30"), std::string::npos);
  // No clock in realtime; every other reason shows.
  for (const char* reason : kReasons) {
    if (std::string(reason) != "foreign_clock") expect_refused(m, reason);
  }
  EXPECT_EQ(m["refused"]["foreign_clock"], 0);
  // The ten plausible forged deposits, and at most the 8 impostor states of
  // UAV 1.
  // Issue 42: and the forwarded deposit; the two served-UAVs chunks as
  // region 0's at the 3 other place agents.
  EXPECT_GE(m["refused_by"]["places"]["foreign_writer"].get<uint64_t>(), 17U) << m["refused_by"].dump(2) << forged;
  EXPECT_LE(m["refused_by"]["places"]["foreign_writer"].get<uint64_t>(), 25U) << m["refused_by"].dump(2) << forged;
  EXPECT_GT(m["refused_by"]["ground"]["foreign_writer"].get<uint64_t>(), 0U) << m["refused_by"].dump(2);
  expect_issue42_refusals(m, /*lockstep=*/false);
}

// ------------------------------------------------------------------ issue 42
// One plausibility rule (core::StateGate): a policy that flies 5 cells a tick
// while it declares max_step 1.5 (tests/plugins/leaper.cpp) on small-test's
// map. The UAVs' gateways refuse its states as the simulator does, a refused
// state is an answer (no lockstep phase waits for it: the run ends well
// inside its 60 s phase timeout and exits 0), and the lockstep run gives the
// simulator's field, series and refusals byte for byte. Domains 82-83.

namespace {

std::string leaper_scenario(const std::string& dir) {
  const std::string path = dir + "/leaper.textproto";
  std::ofstream(path) << "name: \"leaper\"\n"
                      << "map { width: 30 height: 30 tile_size: 6 regions_x: 2 regions_y: 2\n"
                      << "  obstacles { x: 10 y: 6 w: 4 h: 8 } obstacles { x: 18 y: 18 w: 6 h: 3 }\n"
                      << "  targets { x: 22 y: 8 } targets { x: 7 y: 22 } targets { x: 25 y: 26 } }\n"
                      << "swarm { uavs: 4 start_area { x: 1 y: 1 w: 4 h: 4 } }\n"
                      << "run { ticks: 300 tick_rate_hz: 50 seed: 1 }\n"
                      << "policy { plugin { library: \"" << PHEROMESH_TEST_PLUGIN_DIR
                      << "/libpheromesh_test_plugin_leaper.so\" name: \"leaper\" } }\n";
  return path;
}

std::vector<std::string> lines_with(const std::string& text, const std::string& needle) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const auto at = line.find(needle);
    if (at != std::string::npos) out.push_back(line.substr(at));
  }
  return out;
}

}  // namespace

TEST(Plausibility, APolicyFasterThanItsMaxStepGivesTheSimulatorsFieldSeriesAndRefusalsInLockstepAndSaysSo) {
  const std::string dir = out_dir("leaper");
  const std::string scenario = leaper_scenario(dir);
  const Output r = run(kBin + "/pheromesh run " + scenario + " --out " + dir + "/lockstep --domain 82 --progress 0.5 " +
                       "--clock lockstep --ticks 100");
  {
    std::ofstream keep(dir + "/launcher.txt");
    keep << r.text;
  }
  ASSERT_EQ(r.exit_code, 0) << r.text;
  EXPECT_EQ(r.text.find("did not finish within"), std::string::npos) << "a refused state is an answer\n" << r.text;
  // The ground station's log is written like every other process's (D3).
  EXPECT_NE(slurp(dir + "/lockstep/logs/ground.log").find("conducting 100 lockstep ticks"), std::string::npos);
  const Output s = run(kBin + "/pheromesh sim " + scenario + " --quiet --ticks 100 --out " + dir + "/sim");
  ASSERT_EQ(s.exit_code, 0) << s.text;
  const json a = read_metrics(dir + "/lockstep");
  const json b = read_metrics(dir + "/sim");
  ASSERT_TRUE(b.contains("states_refused")) << b.dump(1);
  EXPECT_GT(b["states_refused"]["total"].get<uint64_t>(), 0U);
  for (const char* key : {"ticks", "uavs", "coverage", "covered_cells", "targets_found", "acquisition_ticks",
                          "deposits_sent", "deposits_applied", "deposits_rejected", "field", "states_refused"}) {
    EXPECT_EQ(a.value(key, json()), b.value(key, json())) << key;
  }
  // The same refusals, counted by the same processes (the UAVs' gateways).
  EXPECT_EQ(a["refused_by"]["places"]["implausible_state"], b["refused_by"]["places"]["implausible_state"]);
  EXPECT_EQ(a["refused_by"]["places"]["implausible_state"], b["states_refused"]["total"]);
  EXPECT_EQ(a["refused_by"]["ground"]["implausible_state"], 0) << "counted once, by the gateways";
  expect_accounting(a);
  const std::string field = slurp(dir + "/sim/final_field.txt");
  ASSERT_GT(field.size(), 1000U);
  EXPECT_TRUE(slurp(dir + "/lockstep/final_field.txt") == field) << "final pheromone fields differ";
  const std::string series = slurp(dir + "/sim/series.csv");
  EXPECT_GT(std::count(series.begin(), series.end(), '\n'), 100);
  EXPECT_TRUE(slurp(dir + "/lockstep/series.csv") == series) << "series.csv differs";
  // Both say so, in the same words.
  const auto said_by_sim = lines_with(s.text, "uav 0's policy moved 5 cells in one tick (max_step 1.5): ");
  ASSERT_EQ(said_by_sim.size(), 1U) << s.text;
  EXPECT_EQ(lines_with(r.text, "uav 0's policy moved 5 cells in one tick (max_step 1.5): "), said_by_sim) << r.text;
  EXPECT_EQ(lines_with(r.text, "states refused as implausible in all"),
            lines_with(s.text, "states refused as implausible in all"));
}

TEST(Plausibility, StrictFailsARunWithItsFirstRefusalInTheSimulatorAndInLockstep) {
  const std::string dir = out_dir("leaper-strict");
  const std::string scenario = leaper_scenario(dir);
  const std::string first =
      "--strict: uav 0's state of tick 0 refused as implausible: it moved 5 cells in one tick "
      "from its start cell (max_step 1.5 allows 3 with the slack of 1.5)";
  // `validate` flies the plugin a few ticks and warns before any run.
  const Output v = run(kBin + "/pheromesh validate " + scenario);
  EXPECT_EQ(v.exit_code, 0) << v.text;
  EXPECT_NE(v.text.find("warning     max_step: uav 0's state of tick 0 refused as implausible: it moved 5 cells"),
            std::string::npos)
      << v.text;
  const Output s = run(kBin + "/pheromesh sim " + scenario + " --quiet --strict --ticks 20 --out " + dir + "/sim");
  EXPECT_EQ(s.exit_code, 9) << s.text;
  EXPECT_NE(s.text.find(first), std::string::npos) << s.text;
  const Output r = run(kBin + "/pheromesh run " + scenario + " --out " + dir + "/lockstep --domain 83 --progress 0.5 " +
                       "--clock lockstep --ticks 20 --strict");
  EXPECT_EQ(r.exit_code, 9) << r.text;
  EXPECT_NE(r.text.find(first), std::string::npos) << r.text;
  // Guard: the same runs without --strict pass (above), and an honest
  // declaration passes with --strict.
  const std::string honest = dir + "/honest.textproto";
  std::ofstream(honest) << std::regex_replace(slurp(scenario), std::regex("name: \"leaper\" \\}"),
                                              "name: \"leaper\" config { key: \"max_step\" number: 5 } }");
  const Output h = run(kBin + "/pheromesh sim " + honest + " --quiet --strict --ticks 20 --out " + dir + "/honest");
  EXPECT_EQ(h.exit_code, 0) << h.text;
}
