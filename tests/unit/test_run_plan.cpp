// `pheromesh run`'s plan (launch/run_plan.hpp): which processes a host starts,
// with which arguments, and the deadlines of the run, from the options and
// the scenario alone. The figures are the launcher's as it was before the
// plan was lifted out of it.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "launch/run_plan.hpp"
#include "cli/scenario_overrides.hpp"
#include "pheromesh/bus/cell_discovery.hpp"
#include "pheromesh/runtime/process.hpp"
#include "pheromesh/core/scenario.hpp"

namespace pheromesh::cli {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
using Args = std::vector<std::string>;

const std::string kBin = "/opt/phm/bin";

std::string small_test_path() { return std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto"; }

// small-test: 2 x 2 regions, 4 UAVs, 300 ticks at 50 Hz.
core::ScenarioConfig small_test() {
  auto s = core::load_scenario(small_test_path());
  EXPECT_TRUE(s.ok()) << s.error().message;
  return s.value();
}

// The flat profile, whose participant ids follow the start order; the tests
// of cells, the default, set it back.
RunOptions options() {
  RunOptions o;
  o.scenario = small_test_path();
  o.dds = "cyclone";
  o.dds_profile = "onehost";
  return o;
}

DdsPlan dds(const std::string& spec) {
  auto d = parse_dds_plan(spec, {"cyclone", "fastdds"});
  EXPECT_TRUE(d.ok()) << d.error().message;
  return d.value();
}

RunPlan plan_of(const RunOptions& o, const core::ScenarioConfig& s, const std::string& vendors = "cyclone") {
  auto p = make_run_plan(o, s, dds(vendors), kBin);
  EXPECT_TRUE(p.ok()) << p.error().message;
  return p.value();
}

RunPlan plan_of(const RunOptions& o, const std::string& vendors = "cyclone") {
  return plan_of(o, small_test(), vendors);
}

// small-test with another swarm size (the plan takes the scenario as
// validated: the overrides were applied when it was loaded).
core::ScenarioConfig small_test_with(uint32_t uavs) {
  core::ScenarioConfig s = small_test();
  s.uavs = uavs;
  return s;
}

std::string plan_error(const RunOptions& o) {
  auto p = make_run_plan(o, small_test(), dds("cyclone"), kBin);
  EXPECT_FALSE(p.ok()) << "the plan was accepted";
  return p.ok() ? std::string() : p.error().message;
}

std::vector<std::string> names(const RunPlan& p) {
  std::vector<std::string> n;
  for (const auto& c : p.processes) n.push_back(c.name);
  return n;
}

const PlannedProcess& process(const RunPlan& p, const std::string& name) {
  const auto it = std::find_if(p.processes.begin(), p.processes.end(), [&](const auto& c) { return c.name == name; });
  if (it == p.processes.end()) throw std::runtime_error("no " + name + " in the plan");
  return *it;
}

// The arguments after the common ones (--lease-ms N and what follows it).
Args tail_after_lease(const PlannedProcess& c) {
  const auto it = std::find(c.argv.begin(), c.argv.end(), "--lease-ms");
  if (it == c.argv.end() || it + 1 == c.argv.end()) return {};
  return Args(it + 2, c.argv.end());
}

bool has(const PlannedProcess& c, const std::string& arg) {
  return std::find(c.argv.begin(), c.argv.end(), arg) != c.argv.end();
}

std::string value_of(const PlannedProcess& c, const std::string& flag) {
  const auto it = std::find(c.argv.begin(), c.argv.end(), flag);
  return it == c.argv.end() || it + 1 == c.argv.end() ? std::string("(none)") : *(it + 1);
}

TEST(RunPlan, AFourRegionTenUavLockstepRunStartsTheGroundStationFourPlaceAgentsAndTenUavsInThatOrder) {
  RunOptions o = options();
  o.clock = "lockstep";
  core::ScenarioConfig s = small_test_with(10);
  s.ticks = 50;
  const RunPlan p = plan_of(o, s);
  EXPECT_EQ(names(p),
            (std::vector<std::string>{"ground", "place-0", "place-1", "place-2", "place-3", "uav-0", "uav-1", "uav-2",
                                      "uav-3", "uav-4", "uav-5", "uav-6", "uav-7", "uav-8", "uav-9"}));
  EXPECT_EQ(p.ticks, 50U);
  EXPECT_EQ(p.regions, 4U);
  EXPECT_TRUE(p.lockstep());
  const Args common{kBin + "/pheromesh-ground",
                    "--scenario",
                    small_test_path(),
                    "--dds",
                    "cyclone",
                    "--dds-profile",
                    "onehost",
                    "--domain",
                    "0",
                    "--log-level",
                    "info",
                    "--clock",
                    "lockstep",
                    "--lease-ms",
                    "1000"};
  Args ground = common;
  ground.insert(ground.end(), {"--out", "out/run", "--progress", "1.000000", "--ticks", "50", "--uavs", "10"});
  EXPECT_EQ(process(p, "ground").argv, ground);
  EXPECT_EQ(tail_after_lease(process(p, "place-2")), (Args{"--region", "2", "--ticks", "50"}));
  EXPECT_EQ(tail_after_lease(process(p, "uav-7")), (Args{"--id", "7", "--ticks", "50"}));
  EXPECT_EQ(process(p, "uav-7").executable(), kBin + "/pheromesh-uav");
  EXPECT_EQ(process(p, "place-2").executable(), kBin + "/pheromesh-place");
}

TEST(RunPlan, ParticipantIdsLogFilesAndStandardErrorFollowTheStartOrder) {
  RunOptions o = options();
  o.out_dir = "/tmp/r";
  const RunPlan p = plan_of(o, small_test_with(10));
  for (uint32_t i = 0; i < p.processes.size(); ++i) EXPECT_EQ(p.processes[i].participant_id, i) << p.processes[i].name;
  const PlannedProcess& uav7 = process(p, "uav-7");
  // ground 0, place agents 1..4, uav-0 5; 15 processes on this host
  EXPECT_EQ(uav7.env, (Args{"PHEROMESH_PARTICIPANT_ID=12", "PHEROMESH_SWARM_PROCESSES=15"}));
  EXPECT_EQ(p.host_processes, p.processes.size());
  EXPECT_EQ(uav7.log_path, "/tmp/r/logs/uav-7.log");
  EXPECT_EQ(uav7.stderr_to, StderrTo::Log);
  EXPECT_EQ(process(p, "ground").stderr_to, StderrTo::Launcher);
  // The hubs weigh as much as the herd of UAVs on the host's scheduler.
  EXPECT_EQ(uav7.scheduling, Scheduling::LauncherSession);
  EXPECT_EQ(process(p, "place-2").scheduling, Scheduling::OwnSession);
  EXPECT_EQ(process(p, "ground").scheduling, Scheduling::OwnSession);
  // Realtime: the ground station tells the launcher when it started the
  // swarm (the steady window of metrics.json); lockstep without faults,
  // a console or MAVLink has no control line.
  EXPECT_EQ(process(p, "ground").control, ControlLine::Fd3);
  EXPECT_EQ(value_of(process(p, "ground"), "--launcher-fd"), "3");
  o.clock = "lockstep";
  const RunPlan lockstep = plan_of(o, small_test_with(10));
  EXPECT_EQ(process(lockstep, "ground").control, ControlLine::None);
  // Lockstep: the phases take turns; every process stays in the launcher's session.
  for (const auto& c : lockstep.processes) EXPECT_EQ(c.scheduling, Scheduling::LauncherSession) << c.name;
}

TEST(RunPlan, OptionsGivenArePassedOnAndOptionsLeftOutAreNot) {
  RunOptions o = options();
  const Args bare = tail_after_lease(process(plan_of(o), "uav-1"));
  EXPECT_EQ(bare, (Args{"--id", "1", "--ticks", "300"}));
  o.dds_peers = "a,b";
  o.secure = "/etc/phm";
  o.domain = 9;
  const PlannedProcess uav = process(plan_of(o), "uav-1");
  EXPECT_EQ(tail_after_lease(uav), (Args{"--dds-peers", "a,b", "--secure", "/etc/phm", "--id", "1", "--ticks", "300"}));
  EXPECT_EQ(value_of(uav, "--domain"), "9");
}

TEST(RunPlan, WithOverridesEveryProcessReadsTheChangedScenarioFromTheOutputFolder) {
  RunOptions o = options();
  o.out_dir = "/tmp/r";
  EXPECT_EQ(plan_of(o).process_scenario, small_test_path());
  o.overrides.seed = "7";
  o.overrides.rate = "10";
  auto s = load_overridden(small_test_path(), o.overrides);
  ASSERT_TRUE(s.ok()) << s.error().message;
  const RunPlan p = plan_of(o, s.value());
  EXPECT_EQ(p.process_scenario, "/tmp/r/scenario.textproto");
  EXPECT_EQ(p.rate_hz, 10.0);
  for (const auto& c : p.processes) {
    EXPECT_EQ(value_of(c, "--scenario"), "/tmp/r/scenario.textproto") << c.name;
    // The seed and the rate are in that file, not in flags.
    EXPECT_FALSE(has(c, "--seed")) << c.name;
    EXPECT_FALSE(has(c, "--rate")) << c.name;
  }
}

TEST(RunPlan, StandbyStartsAReplicaOfEveryRegionAfterThePrimariesAndEveryProcessTakesStandby) {
  RunOptions o = options();
  core::ScenarioConfig standby = small_test();
  standby.standby = true;  // --standby: --set run.standby=true
  const RunPlan p = plan_of(o, standby);
  EXPECT_EQ(p.standby, Standby::FromStart);
  EXPECT_EQ(names(p),
            (std::vector<std::string>{"ground", "place-0", "place-1", "place-2", "place-3", "place-0.r1", "place-1.r1",
                                      "place-2.r1", "place-3.r1", "uav-0", "uav-1", "uav-2", "uav-3"}));
  EXPECT_EQ(tail_after_lease(process(p, "place-1.r1")),
            (Args{"--standby", "--replica", "1", "--region", "1", "--ticks", "300"}));
  for (const auto& c : p.processes) {
    EXPECT_TRUE(has(c, "--standby")) << c.name;
    // Exclusive ownership in an all-Cyclone swarm.
    EXPECT_FALSE(has(c, "--shared-ownership")) << c.name;
  }
  const RunPlan fast = plan_of(o, standby, "fastdds");
  for (const auto& c : fast.processes) EXPECT_TRUE(has(c, "--shared-ownership")) << c.name;
}

TEST(RunPlan, TheScenariosStandbyStartsReplicasLikeTheFlag) {
  core::ScenarioConfig s = small_test();
  s.standby = true;
  auto p = make_run_plan(options(), s, dds("cyclone"), kBin);
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p->processes.size(), 13U);
  EXPECT_EQ(p->replicas_at_start(), 2U);
}

TEST(RunPlan, AMixedVendorRunAlternatesPlaceAgentsFromCycloneAndUavsFromFastDds) {
  RunOptions o = options();
  core::ScenarioConfig standby = small_test();
  standby.standby = true;
  const RunPlan p = plan_of(o, standby, "mixed");
  const std::vector<std::pair<std::string, std::string>> expected{
      {"ground", "cyclone"},  {"place-0", "cyclone"},    {"place-1", "fastdds"},    {"place-2", "cyclone"},
      {"place-3", "fastdds"}, {"place-0.r1", "cyclone"}, {"place-1.r1", "fastdds"}, {"uav-0", "fastdds"},
      {"uav-1", "cyclone"},   {"uav-2", "fastdds"},      {"uav-3", "cyclone"}};
  for (const auto& [name, vendor] : expected) {
    EXPECT_EQ(process(p, name).dds, vendor) << name;
    EXPECT_EQ(value_of(process(p, name), "--dds"), vendor) << name;
  }
  // Not one vendor: shared ownership for every process.
  for (const auto& c : p.processes) EXPECT_TRUE(has(c, "--shared-ownership")) << c.name;
}

TEST(RunPlan, AHostOfAMultiHostSwarmStartsOnlyItsShare) {
  RunOptions o = options();
  core::ScenarioConfig s = small_test_with(10);
  s.standby = true;
  o.hosts = 3;
  o.host_index = 1;
  o.ground_host = 0;
  o.dds_profile = "lan";
  const RunPlan p = plan_of(o, s);
  // Place agent R replica N on host (R + N) % 3, UAV U on the host of its
  // home place agent U % 4.
  EXPECT_EQ(names(p), (std::vector<std::string>{"place-1", "place-0.r1", "place-3.r1", "uav-1", "uav-5", "uav-9"}));
  EXPECT_EQ(p.processes.front().participant_id, 0U);
  EXPECT_EQ(p.processes.back().participant_id, 5U);
  EXPECT_EQ(p.deadlines.other_hosts, seconds(60));
  ASSERT_EQ(p.stop_early.size(), 3U);
  EXPECT_EQ(p.stop_early[1].role, "place");
  EXPECT_EQ(p.stop_early[2].role, "ground");
  EXPECT_EQ(p.stop_early[2].grace, seconds(15));

  o.host_index = 0;
  const RunPlan ground_host = plan_of(o, s);
  EXPECT_EQ(ground_host.processes.front().name, "ground");
  EXPECT_TRUE(has(ground_host.processes.front(), "--until-done"));
  // The ground station; place-0, place-3; place-2.r1; uav-0, 3, 4, 7, 8.
  EXPECT_EQ(ground_host.processes.size(), 1U + 2U + 1U + 5U);
}

TEST(RunPlan, MultiHostChecksNameTheProfileTheKeyAndAFaultOfAnotherHost) {
  RunOptions o = options();
  o.hosts = 2;
  o.host_index = 1;
  EXPECT_NE(check_multi_host(plan_of(o), ControlKey::Set).value_or("").find("keeps traffic on this host"),
            std::string::npos);
  // Cells, the default, need every host's address.
  RunOptions cells = o;
  cells.dds_profile.clear();  // none given: cells
  EXPECT_NE(plan_error(cells).find("needs --dds-peers with every host's address in host-index order"),
            std::string::npos)
      << plan_error(cells);
  cells.host_addresses = {"10.0.0.1"};
  EXPECT_NE(plan_error(cells).find("got 1"), std::string::npos) << plan_error(cells);
  cells.host_addresses = {"10.0.0.1", "10.0.0.2"};
  EXPECT_EQ(check_multi_host(plan_of(cells), ControlKey::Set), std::nullopt);
  o.dds_profile = "lan";
  EXPECT_EQ(check_multi_host(plan_of(o), ControlKey::Set), std::nullopt);
  const auto unset = check_multi_host(plan_of(o), ControlKey::Unset).value_or("");
  EXPECT_NE(unset.find("$PHEROMESH_CONTROL_KEY"), std::string::npos) << unset;
  EXPECT_EQ(unset.find("malformed"), std::string::npos) << unset;
  EXPECT_NE(
      check_multi_host(plan_of(o), ControlKey::Malformed, "odd length").value_or("").find("malformed: odd length"),
      std::string::npos);
  o.faults_spec = "kill uav:0 @2s";
  EXPECT_NE(check_multi_host(plan_of(o), ControlKey::Set).value_or("").find("uav-0 does not run on host 1"),
            std::string::npos);
  o.host_index = 2;
  EXPECT_EQ(check_multi_host(plan_of(o), ControlKey::Set).value_or(""),
            "--host-index 2 is not below --hosts 2 (hosts are numbered 0..1)");
}

TEST(RunPlan, RealtimeDeadlinesComeFromTicksRateAndTheNumberOfProcesses) {
  const RunPlan p = plan_of(options());
  // Twice 300 ticks at 50 Hz, 45 s, 200 ms for each of the 9 processes.
  EXPECT_EQ(p.deadlines.uavs_end, milliseconds(12000 + 45000 + 9 * 200));
  EXPECT_EQ(p.deadlines.resource_sample, milliseconds(3600));  // 60 % of 6 s
  EXPECT_EQ(p.deadlines.conductor_grace, milliseconds(6 * 1000 + 15000));
  EXPECT_EQ(p.deadlines.other_hosts, seconds(0));
  ASSERT_EQ(p.stop_early.size(), 1U);
  EXPECT_EQ(p.stop_early[0].role, "uav");
  EXPECT_EQ(p.stop_early[0].grace, seconds(10));
  ASSERT_EQ(p.stop_final.size(), 2U);
  EXPECT_EQ(p.stop_final[0].role, "place");
  EXPECT_EQ(p.stop_final[1].role, "ground");

  RunOptions slow = options();
  slow.lease_ms = 2000;
  core::ScenarioConfig slow_scenario = small_test();
  slow_scenario.tick_rate_hz = 10;
  const RunPlan q = plan_of(slow, slow_scenario);
  EXPECT_EQ(q.deadlines.uavs_end, milliseconds(60000 + 45000 + 9 * 200));
  EXPECT_EQ(q.deadlines.resource_sample, milliseconds(18000));
  EXPECT_EQ(q.deadlines.conductor_grace, milliseconds(12000 + 15000));
}

TEST(RunPlan, ALockstepRunHasAYearForItsUavsTheConductorBoundsIt) {
  RunOptions o = options();
  o.clock = "lockstep";
  const RunPlan p = plan_of(o);
  EXPECT_EQ(p.deadlines.uavs_end, milliseconds(int64_t{365} * 24 * 3600 * 1000 + 45000 + 9 * 200));
}

TEST(RunPlan, DurationBecomesTicksAtTheRunsRate) {
  RunOptions o = options();
  o.overrides.duration_s = 2.01;
  auto s = load_overridden(small_test_path(), o.overrides);
  ASSERT_TRUE(s.ok()) << s.error().message;
  const RunPlan p = plan_of(o, s.value());
  EXPECT_EQ(p.ticks, 101U);  // ceil(2.01 s x 50 Hz)
  EXPECT_EQ(value_of(process(p, "uav-0"), "--ticks"), "101");
  EXPECT_EQ(value_of(process(p, "ground"), "--ticks"), "101");
}

TEST(RunPlan, MoreThanSixtyFourProcessesStartTheUavsInBatchesAtTheStartRate) {
  RunOptions o = options();
  // 1 + 4 + 59 = 64: all at once
  EXPECT_FALSE(plan_of(o, small_test_with(59)).stagger.has_value());
  const core::ScenarioConfig sixty = small_test_with(60);
  const auto s = plan_of(o, sixty).stagger;
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->batch, 5U);  // a tenth of a second of 50 per second
  EXPECT_EQ(s->pause, milliseconds(100));
  o.start_rate = 7;
  EXPECT_EQ(plan_of(o, sixty).stagger->batch, 1U);
  EXPECT_EQ(plan_of(o, sixty).stagger->pause, milliseconds(142));
  o.start_rate = 0;
  EXPECT_FALSE(plan_of(o, sixty).stagger.has_value());
}

TEST(RunPlan, LockstepFaultsGiveTheGroundStationTheControlLineAndTheirTicks) {
  RunOptions o = options();
  o.clock = "lockstep";
  o.faults_spec = "stop place:2 @8t for 1s; kill uav:1 @5t";
  const RunPlan p = plan_of(o);
  ASSERT_TRUE(p.faults.has_value());
  EXPECT_EQ(p.faults->events.size(), 2U);
  const PlannedProcess& g = process(p, "ground");
  EXPECT_EQ(g.control, ControlLine::Fd3);
  EXPECT_EQ(value_of(g, "--launcher-fd"), "3");
  EXPECT_EQ(value_of(g, "--fault-ticks"), "5,8");
}

TEST(RunPlan, TheWebConsoleRecordsToTheOutputFolderUnlessToldOtherwise) {
  RunOptions o = options();
  o.http_port = 8080;
  const PlannedProcess g = process(plan_of(o), "ground");
  EXPECT_EQ(g.control, ControlLine::Fd3);
  const Args tail(std::find(g.argv.begin(), g.argv.end(), "--launcher-fd"), g.argv.end());
  EXPECT_EQ(tail, (Args{"--launcher-fd", "3", "--http", "8080", "--http-bind", "127.0.0.1", "--record",
                        "out/run/console.phrec"}));
  o.no_record = true;
  EXPECT_FALSE(has(process(plan_of(o), "ground"), "--record"));
  o.no_record = false;
  o.record = "/tmp/x.phrec";
  EXPECT_EQ(value_of(process(plan_of(o), "ground"), "--record"), "/tmp/x.phrec");
}

TEST(RunPlan, MavlinkGoesToTheGroundStationOnlyAndOnlyWhenAsked) {
  RunOptions o = options();
  EXPECT_FALSE(has(process(plan_of(o), "ground"), "--mavlink"));
  o.mavlink = "udp:127.0.0.1:14550";
  o.mavlink_rate_hz = 2.5;
  const RunPlan p = plan_of(o);
  EXPECT_EQ(value_of(process(p, "ground"), "--mavlink"), "udp:127.0.0.1:14550");
  EXPECT_DOUBLE_EQ(std::stod(value_of(process(p, "ground"), "--mavlink-rate-hz")), 2.5);
  // The line to the launcher: a station's pause extends the deadline, its stop ends the run.
  EXPECT_EQ(process(p, "ground").control, ControlLine::Fd3);
  EXPECT_EQ(value_of(process(p, "ground"), "--launcher-fd"), "3");
  for (const PlannedProcess& c : p.processes) {
    if (c.name != "ground") EXPECT_FALSE(has(c, "--mavlink")) << c.name;
  }
}

TEST(RunPlan, AStandbyFaultMakesEveryProcessAStandbyRunWithoutStartingReplicas) {
  RunOptions o = options();
  o.faults_spec = "standby place:1 @2s";
  const RunPlan p = plan_of(o);
  EXPECT_EQ(p.standby, Standby::OnFault);
  EXPECT_EQ(p.processes.size(), 9U);
  for (const auto& c : p.processes) EXPECT_TRUE(has(c, "--standby")) << c.name;
  ASSERT_EQ(p.notes.size(), 1U);
  EXPECT_EQ(p.notes[0].text, "fault schedule: 'standby' events: every process runs with --standby");
  // --secure: the standbys a fault may start need their identities too.
  const auto ids = p.identities();
  EXPECT_EQ(ids.size(), 1U + 8U + 4U);
  EXPECT_NE(std::find(ids.begin(), ids.end(), "place-3.r1"), ids.end());
}

TEST(RunPlan, NetworkFaultsMoveTheOneHostProfileToNetnsAndRefuseTheWebConsole) {
  RunOptions o = options();
  o.faults_spec = "loss 20% @1s for 2s";
  const RunPlan p = plan_of(o);
  EXPECT_EQ(p.options.dds_profile, "netns");
  EXPECT_EQ(value_of(process(p, "uav-0"), "--dds-profile"), "netns");
  EXPECT_TRUE(p.notes.empty());
  o.dds_profile = "lan";
  const RunPlan lan = plan_of(o);
  EXPECT_EQ(lan.options.dds_profile, "lan");
  ASSERT_EQ(lan.notes.size(), 1U);
  EXPECT_EQ(lan.notes[0].level, PlanNote::Level::Warn);
  o.http_port = 8080;
  EXPECT_NE(plan_error(o).find("leave out --http or the network faults"), std::string::npos);
}

TEST(RunPlan, AScheduleThatCannotRunIsRefusedNamingWhereItCameFrom) {
  RunOptions o = options();
  o.faults_spec = "kill ground @1s";
  EXPECT_NE(plan_error(o).find("the ground station cannot be killed or restarted"), std::string::npos);
  o.faults_spec = "kill uav:9 @1s";
  EXPECT_EQ(plan_error(o).rfind("--faults: ", 0), 0U);
  o.faults_spec.clear();
  o.kill_spec = "uav:2@5t";  // ticks in a realtime run
  EXPECT_EQ(plan_error(o).rfind("--kill: ", 0), 0U);
}

TEST(RunPlan, ARestartedUavFliesTheTicksLeftWithItsDepositsNumberedAboveItsEarlierLives) {
  const RunPlan p = plan_of(options());
  const PlannedProcess again = p.restarted_uav(2, 40, 1U << 24U, 6);
  EXPECT_EQ(again.name, "uav-2");
  EXPECT_EQ(tail_after_lease(again), (Args{"--id", "2", "--ticks", "40", "--seq-base", "16777216"}));
  EXPECT_EQ(again.env,
            (Args{"PHEROMESH_PARTICIPANT_ID=6", "PHEROMESH_SWARM_PROCESSES=" + std::to_string(p.processes.size())}));
  const PlannedProcess standby = p.place(3, 2, 9);
  EXPECT_EQ(standby.name, "place-3.r2");
  EXPECT_EQ(value_of(standby, "--replica"), "2");
}

TEST(RunPlan, SecureFastDdsProcessesStartThreeHundredMillisecondsApart) {
  RunOptions o = options();
  o.secure = "/etc/phm";
  EXPECT_EQ(plan_of(o, "fastdds").spawn_gap, milliseconds(300));
  EXPECT_EQ(plan_of(o, "cyclone").spawn_gap, milliseconds(0));
  o.secure.clear();
  EXPECT_EQ(plan_of(o, "fastdds").spawn_gap, milliseconds(0));
}

}  // namespace
}  // namespace pheromesh::cli

namespace pheromesh::cli {
namespace {

// --dds-profile cells (docs/dds.md, "Cell discovery"): each process is
// told whom to announce itself to, and nobody else.
std::string env_of(const PlannedProcess& c, const std::string& name) {
  for (const auto& e : c.env) {
    if (e.rfind(name + "=", 0) == 0) return e.substr(name.size() + 1);
  }
  return "(unset)";
}

TEST(RunPlan, ARunWithoutALeaseTakesOneSecondAndAHostOfHundredsOfProcessesFiveSaidInANote) {
  const RunPlan small = plan_of(options(), small_test_with(10));
  EXPECT_EQ(small.options.lease_ms, 1000U);
  EXPECT_EQ(value_of(process(small, "uav-0"), "--lease-ms"), "1000");
  EXPECT_TRUE(small.notes.empty());
  const RunPlan big = plan_of(options(), small_test_with(150));  // 155 processes
  EXPECT_EQ(big.options.lease_ms, 5000U);
  EXPECT_EQ(value_of(process(big, "uav-149"), "--lease-ms"), "5000");
  ASSERT_EQ(big.notes.size(), 1U);
  EXPECT_NE(big.notes[0].text.find("155 processes on this host: liveliness lease 5000 ms"), std::string::npos)
      << big.notes[0].text;
  RunOptions given = options();
  given.lease_ms = 700;
  EXPECT_EQ(plan_of(given, small_test_with(150)).options.lease_ms, 700U) << "a lease given is kept";
}

TEST(RunPlan, ARunWithoutAProfileFliesInCells) {
  RunOptions o;
  o.scenario = small_test_path();
  o.dds = "cyclone";
  EXPECT_EQ(o.dds_profile, "");  // none given
  const RunPlan p = plan_of(o, small_test_with(10));
  ASSERT_TRUE(p.cells.has_value());
  EXPECT_EQ(p.options.dds_profile, "cells");
  EXPECT_TRUE(p.notes.empty());
  EXPECT_EQ(value_of(process(p, "uav-0"), "--dds-profile"), "cells");
  EXPECT_NE(env_of(process(p, "uav-0"), "PHEROMESH_CELL"), "(unset)");
  EXPECT_EQ(cells_attach_command(p).value_or(""), "pheromesh attach --domain 0 --cell-hubs 5");
  // A secure swarm's monitor authenticates from the same directory.
  o.secure = "/etc/swarm-sec";
  EXPECT_EQ(cells_attach_command(plan_of(o, small_test_with(10))).value_or(""),
            "pheromesh attach --domain 0 --cell-hubs 5 --secure /etc/swarm-sec");
}

TEST(RunPlan, ARunWithoutAProfileWhoseCellsCannotBeOnOneHostFliesFlatAndSaysWhyButCellsAskedForAreRefused) {
  RunOptions o;
  o.scenario = small_test_path();
  o.dds = "cyclone";
  o.domain = 121;  // the hubs' well-known ports would be past 32767
  const RunPlan p = plan_of(o, small_test_with(10));
  EXPECT_FALSE(p.cells.has_value());
  EXPECT_EQ(p.options.dds_profile, "onehost");
  ASSERT_EQ(p.notes.size(), 1U);
  EXPECT_EQ(p.notes[0].level, PlanNote::Level::Warn);
  EXPECT_NE(p.notes[0].text.find("ephemeral"), std::string::npos) << p.notes[0].text;
  o.dds_profile = "cells";
  EXPECT_NE(plan_error(o).find("ephemeral"), std::string::npos) << plan_error(o);
  // Over several hosts there is no flat profile to fall back to.
  o.dds_profile.clear();
  o.hosts = 2;
  o.host_addresses = {"10.0.0.1", "10.0.0.2"};
  EXPECT_NE(plan_error(o).find("ephemeral"), std::string::npos) << plan_error(o);
}

TEST(RunPlan, InCellsOverSeveralHostsEachProcessBindsItsHostsAddressAndNamesItsPeersAtTheirs) {
  RunOptions o = options();
  o.dds_profile = "cells";
  o.hosts = 3;
  o.host_index = 2;
  o.host_addresses = {"10.0.0.1", "10.0.0.2", "10.0.0.3"};
  o.dds_peers = "10.0.0.1,10.0.0.2,10.0.0.3";
  const RunPlan p = plan_of(o, small_test_with(10));
  // Host 2: place agent 2 and the UAVs whose home it is (2 and 6).
  EXPECT_EQ(names(p), (std::vector<std::string>{"place-2", "uav-2", "uav-6"}));
  EXPECT_EQ(env_of(process(p, "uav-6"), "PHEROMESH_CELL"), "peers=10.0.0.3:0;reserve=10.0.0.1:2;iface=10.0.0.3");
  EXPECT_EQ(env_of(process(p, "place-2"), "PHEROMESH_PARTICIPANT_ID"), "0");
  // The processes take their peers from the cell, not --dds-peers.
  EXPECT_FALSE(has(process(p, "uav-6"), "--dds-peers"));
  EXPECT_EQ(cells_attach_command(p).value_or(""),
            "pheromesh attach --domain 0 --cell-hubs 3 --dds-peers 10.0.0.1,10.0.0.2,10.0.0.3");
  // --pin-uavs: UAV 6 flies on host 0 instead, UAV 1 (home 1, host 1) here;
  // each still names its home at its host's address and binds its own.
  o.pin_uavs = "6=0,1=2";
  const RunPlan pinned = plan_of(o, small_test_with(10));
  EXPECT_EQ(names(pinned), (std::vector<std::string>{"place-2", "uav-1", "uav-2"}));
  EXPECT_EQ(env_of(process(pinned, "uav-1"), "PHEROMESH_CELL"), "peers=10.0.0.2:0;reserve=10.0.0.3:0;iface=10.0.0.3");
  o.pin_uavs = "1=3";
  EXPECT_NE(plan_error(o).find("--pin-uavs: '1=3': the hosts are 0..2"), std::string::npos) << plan_error(o);
}

TEST(RunPlan, InCellsAUavNamesItsHomeAndKeepsItsBackupInReserveAndTheHubsNameOneAnother) {
  RunOptions o = options();
  o.dds_profile = "cells";
  o.domain = 3;
  const RunPlan p = plan_of(o, small_test_with(10), "fastdds");  // 4 regions
  // The ground station is hub 0, place agent r hub 1 + r.
  EXPECT_EQ(env_of(process(p, "ground"), "PHEROMESH_CELL"),
            "index=0;peers=127.0.0.1:1,127.0.0.1:2,127.0.0.1:3,127.0.0.1:4");
  EXPECT_EQ(env_of(process(p, "place-2"), "PHEROMESH_CELL"),
            "index=3;peers=127.0.0.1:0,127.0.0.1:1,127.0.0.1:2,127.0.0.1:4");
  // UAV 6: home 6 mod 4 = 2 (hub 3), backup 3 (hub 4), named only once the
  // home is gone (realtime); a member (no index), its Fast DDS id past every
  // index a hub can have (120 + 6).
  EXPECT_EQ(env_of(process(p, "uav-6"), "PHEROMESH_CELL"), "peers=127.0.0.1:3;reserve=127.0.0.1:4");
  EXPECT_EQ(env_of(process(p, "uav-6"), "PHEROMESH_PARTICIPANT_ID"), "126");
  EXPECT_EQ(env_of(process(p, "place-2"), "PHEROMESH_PARTICIPANT_ID"), "3");
  // What every process parses back is the cell it was given.
  const auto cell = bus::parse_cell(env_of(process(p, "uav-6"), "PHEROMESH_CELL"), 3);
  ASSERT_TRUE(cell.ok()) << cell.error().message;
  EXPECT_EQ(cell->domain, 3U);
  EXPECT_FALSE(cell->index.has_value());
  ASSERT_EQ(cell->peers.size(), 1U);
  EXPECT_EQ(cell->peers[0].index, 3U);
  ASSERT_EQ(cell->reserve.size(), 1U);
  EXPECT_EQ(cell->reserve[0].index, 4U);
  // In lockstep the backup relays the clock that tells the UAV its home is
  // gone: it is named from the start.
  RunOptions lock = o;
  lock.clock = "lockstep";
  EXPECT_EQ(env_of(process(plan_of(lock, small_test_with(10), "fastdds"), "uav-6"), "PHEROMESH_CELL"),
            "peers=127.0.0.1:3,127.0.0.1:4");
  // With standbys a UAV names both replicas of each gateway (the standby of
  // region r is hub 1 + regions + r).
  core::ScenarioConfig replicated = small_test_with(10);
  replicated.standby = true;
  const RunPlan s = plan_of(o, replicated, "fastdds");
  EXPECT_EQ(env_of(process(s, "uav-6"), "PHEROMESH_CELL"), "peers=127.0.0.1:3,127.0.0.1:7;reserve=127.0.0.1:4,127.0.0.1:8");
  EXPECT_EQ(env_of(process(s, "place-2.r1"), "PHEROMESH_CELL").rfind("index=7;peers=127.0.0.1:0,", 0), 0U);
  EXPECT_EQ(env_of(process(s, "uav-6"), "PHEROMESH_PARTICIPANT_ID"), "126");
}

TEST(RunPlan, CellsGiveWayToTheFlatProfileThatNetworkFaultsOrADiscoveryServerNeedAndRefusePortsTheyCannotHave) {
  RunOptions o = options();
  o.dds_profile = "cells";
  o.faults_spec = "loss 20% @1s for 2s";
  const RunPlan lossy = plan_of(o);
  EXPECT_EQ(lossy.options.dds_profile, "netns");
  EXPECT_FALSE(lossy.cells.has_value());
  ASSERT_EQ(lossy.notes.size(), 1U);
  EXPECT_NE(lossy.notes[0].text.find("instead of cells"), std::string::npos) << lossy.notes[0].text;
  o.faults_spec.clear();
  o.discovery_server = true;
  const RunPlan served = plan_of(o);
  EXPECT_EQ(served.options.dds_profile, "onehost");
  ASSERT_EQ(served.notes.size(), 1U);
  EXPECT_NE(served.notes[0].text.find("not in cells"), std::string::npos);
  o.discovery_server = false;
  o.domain = 102;  // the hubs' ports on domain 102 are past 32767
  EXPECT_NE(plan_error(o).find("ephemeral"), std::string::npos) << plan_error(o);
}

TEST(CellText, AMalformedCellNamesThePartThatIsWrong) {
  EXPECT_FALSE(bus::parse_cell("", 0).ok());
  EXPECT_NE(bus::parse_cell("index=x;peers=127.0.0.1:1", 0).error().message.find("index 'x'"), std::string::npos);
  EXPECT_NE(bus::parse_cell("peers=127.0.0.1", 0).error().message.find("peer '127.0.0.1'"), std::string::npos);
  EXPECT_NE(bus::parse_cell("index=1;port=3", 0).error().message.find("unknown part 'port'"), std::string::npos);
  EXPECT_NE(bus::parse_cell("index=200;peers=127.0.0.1:1", 0).error().message.find("above 119"), std::string::npos);
  EXPECT_NE(bus::parse_cell("peers=host:1", 0).error().message.find("not an IPv4 address"), std::string::npos);
  EXPECT_NE(bus::parse_cell("reserve=127.0.0.1:1", 0).error().message.find("no peers"), std::string::npos);
  EXPECT_NE(bus::parse_cell("peers=127.0.0.1:1;reserve=127.0.0.1:300", 0).error().message.find("reserve peer"),
            std::string::npos);
  bus::CellDiscovery c;
  c.index = 5;
  c.peers = {{"127.0.0.1", 0}, {"10.0.0.2", 7}};
  const auto back = bus::parse_cell(bus::format_cell(c), 9);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(*back->index, 5U);
  EXPECT_EQ(back->peers[1].address, "10.0.0.2");
  EXPECT_EQ(back->peers[1].index, 7U);
  EXPECT_TRUE(back->reserve.empty());
  c.index.reset();
  c.reserve = {{"127.0.0.1", 4}};
  EXPECT_EQ(bus::format_cell(c), "peers=127.0.0.1:0,10.0.0.2:7;reserve=127.0.0.1:4");
  const auto member = bus::parse_cell(bus::format_cell(c), 9);
  ASSERT_TRUE(member.ok()) << member.error().message;
  ASSERT_EQ(member->reserve.size(), 1U);
  EXPECT_EQ(member->reserve[0].index, 4U);
  EXPECT_EQ(back->domain, 9U);
}

}  // namespace
}  // namespace pheromesh::cli

namespace pheromesh::cli {
namespace {

// A process reads its cell from $PHEROMESH_CELL (runtime::bus_options).
TEST(CellText, AProcessTakesItsCellFromTheEnvironmentAndAFastDdsMemberNeedsAnId) {
  runtime::CommonOptions o;
  o.domain = 7;
  o.dds = "fastdds";
  ::setenv(bus::kCellEnv, "peers=127.0.0.1:1,127.0.0.1:2", 1);
  ::unsetenv("PHEROMESH_PARTICIPANT_ID");
  const auto without_id = runtime::bus_options(o, "uav-0");
  ASSERT_FALSE(without_id.ok());
  EXPECT_NE(without_id.error().message.find("needs its own participant id"), std::string::npos);
  ::setenv("PHEROMESH_PARTICIPANT_ID", "9", 1);
  const auto with_id = runtime::bus_options(o, "uav-0");
  ASSERT_TRUE(with_id.ok()) << with_id.error().message;
  ASSERT_TRUE(with_id->cell.has_value());
  EXPECT_EQ(with_id->cell->domain, 7U);
  EXPECT_EQ(with_id->cell->peers.size(), 2U);
  EXPECT_EQ(with_id->participant_id, 9);
  ::setenv(bus::kCellEnv, "peers=nowhere", 1);
  EXPECT_FALSE(runtime::bus_options(o, "uav-0").ok());
  ::unsetenv(bus::kCellEnv);
  ::unsetenv("PHEROMESH_PARTICIPANT_ID");
  o.dds_profile = "cells";
  const auto no_cell = runtime::bus_options(o, "uav-0");
  ASSERT_FALSE(no_cell.ok());
  EXPECT_NE(no_cell.error().message.find("has no cell"), std::string::npos);
}

}  // namespace
}  // namespace pheromesh::cli
