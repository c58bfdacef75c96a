// The end of `pheromesh run` (launch/metrics_merge.hpp): the ground station's
// metrics.json merged with the processes the launcher saw end, and the
// run's exit code from how they ended.
#include <gtest/gtest.h>

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <optional>
#include <fstream>
#include <sstream>
#include <vector>

#include "launch/metrics_merge.hpp"
#include "json_schema_subset.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/report/report.hpp"

namespace pheromesh::cli {
namespace {

ChildProcess ended(const std::string& name, const std::string& role, int exit_code, int term_signal = 0) {
  ChildProcess c;
  c.name = name;
  c.role = role;
  c.dds = "cyclone";
  c.pid = 100;
  c.running = false;
  c.reaped = true;
  c.exit_code = exit_code;
  c.term_signal = term_signal;
  return c;
}

nlohmann::json ground_metrics() { return {{"coverage", 0.5}, {"targets_found", 2}}; }

RunRecord record_of(const std::vector<ChildProcess>& processes, uint32_t ticks_asked = 0) {
  RunRecord r;
  r.ticks_asked = ticks_asked;
  r.processes = processes;
  r.faults = {{"faults", nlohmann::json::array()}, {"faults_failed", 0}};
  r.dds = "cyclone";
  return r;
}

TEST(MetricsMerge, AProcessKilledOnPurposeCountsAsKilledAndTheRunSucceeds) {
  std::vector<ChildProcess> ps{ended("ground", "ground", 0), ended("uav-0", "uav", 0),
                               ended("uav-1", "uav", -1, SIGKILL)};
  ps[2].killed_on_purpose = true;
  const MergedMetrics m = merge_metrics(ground_metrics(), record_of(ps), "out/metrics.json");
  EXPECT_EQ(m.exit_code(), 0);
  EXPECT_EQ(m.killed, 1U);
  EXPECT_EQ(m.crashed, 0U);
  EXPECT_TRUE(m.errors.empty());
  EXPECT_EQ(m.metrics["processes_killed"], 1);
  EXPECT_EQ(m.metrics["processes_crashed"], 0);
  EXPECT_EQ(m.metrics["processes"][2]["status"], std::string("killed by ") + strsignal(SIGKILL) + " (on purpose)");
  EXPECT_EQ(m.metrics["processes"][2]["crashed"], false);
  // The ground station's figures are kept.
  EXPECT_EQ(m.metrics["coverage"], 0.5);
  EXPECT_EQ(m.metrics["targets_found"], 2);
}

TEST(MetricsMerge, KilledUavsAndPlaceAgentsAreCountedByRoleFromWhatTheLauncherKilled) {
  // A realtime ground station counts no kills of its own (it said
  // places_killed 0 after a place agent's kill); the launcher's count wins.
  std::vector<ChildProcess> ps{ended("ground", "ground", 0), ended("place-0", "place", -1, SIGKILL),
                               ended("place-0.r1", "place", -1, SIGKILL), ended("place-1", "place", 0),
                               ended("uav-0", "uav", -1, SIGKILL), ended("uav-1", "uav", 0)};
  ps[1].killed_on_purpose = ps[2].killed_on_purpose = ps[4].killed_on_purpose = true;
  nlohmann::json ground = ground_metrics();
  ground["places_killed"] = 0;
  ground["uavs_killed"] = 0;
  const MergedMetrics m = merge_metrics(ground, record_of(ps), "out/metrics.json");
  EXPECT_EQ(m.metrics["places_killed"], 2);  // processes, as the simulator counts a standby
  EXPECT_EQ(m.metrics["uavs_killed"], 1);
  EXPECT_EQ(m.metrics["processes_killed"], 3);
  // Nobody killed, and the ground station wrote no such keys: none are added.
  const MergedMetrics calm = merge_metrics(ground_metrics(), record_of({ended("uav-0", "uav", 0)}), "m.json");
  EXPECT_FALSE(calm.metrics.contains("places_killed"));
}

TEST(MetricsMerge, UavsTheGroundStationNeverHeardFailTheRunUnlessKilledOnPurpose) {
  // 4 UAVs asked for, 2 heard: the host did not bring up the swarm (a
  // 300-UAV run once flew nothing and exited 0).
  std::vector<ChildProcess> ps{ended("ground", "ground", 0), ended("uav-0", "uav", 0), ended("uav-1", "uav", 0),
                               ended("uav-2", "uav", 0), ended("uav-3", "uav", -1, SIGKILL)};
  for (uint32_t u = 0; u < 4; ++u) ps[u + 1].index = u;
  nlohmann::json g = ground_metrics();
  g["uavs"] = 2;
  g["uavs_expected"] = 4;
  MergedMetrics m = merge_metrics(g, record_of(ps), "out/metrics.json");
  EXPECT_EQ(m.exit_code(), 1);
  ASSERT_FALSE(m.errors.empty());
  EXPECT_NE(m.errors[0].find("2 of 4 UAVs were never heard"), std::string::npos) << m.errors[0];
  // UAV 3 killed on purpose before it was heard, and UAV 2's silence is
  // still unexplained.
  ps[4].killed_on_purpose = true;
  m = merge_metrics(g, record_of(ps), "out/metrics.json");
  EXPECT_EQ(m.exit_code(), 1);
  g["uavs"] = 3;
  m = merge_metrics(g, record_of(ps), "out/metrics.json");
  EXPECT_EQ(m.exit_code(), 0) << "three heard, the fourth killed on purpose";
  EXPECT_TRUE(m.errors.empty());
}

// A ground station's metrics of 3 UAVs asked for 100 ticks each: their
// latest ticks heard and whether each finished.
nlohmann::json flown(std::vector<std::pair<uint32_t, bool>> uavs) {
  nlohmann::json g = ground_metrics();
  g["ticks"] = 100;  // the last tick reached; the ticks asked come from the plan (record_of)
  g["uavs_expected"] = uavs.size();
  g["uavs"] = uavs.size();
  for (std::size_t u = 0; u < uavs.size(); ++u) {
    g["uav_status"][std::to_string(u)] = {{"last_tick", uavs[u].first}, {"heard_tick", uavs[u].first},
                                          {"finished", uavs[u].second}};
  }
  return g;
}

std::vector<ChildProcess> three_uavs() {
  std::vector<ChildProcess> ps{ended("ground", "ground", 0)};
  for (uint32_t u = 0; u < 3; ++u) {
    ps.push_back(ended("uav-" + std::to_string(u), "uav", 0));
    ps.back().index = u;
  }
  return ps;
}

TEST(MetricsMerge, ASwarmThatFlewUnderNinetyPercentOfTheTicksAskedFailsTheRunWithEight) {
  // 270 of 300 ticks: exactly 90 %, the run stands.
  MergedMetrics m = merge_metrics(flown({{100, true}, {100, true}, {70, true}}), record_of(three_uavs(), 100), "m.json");
  EXPECT_FALSE(m.shortfall.has_value()) << *m.shortfall;
  EXPECT_EQ(m.exit_code(), 0);
  // 269 of 300: it does not.
  m = merge_metrics(flown({{100, true}, {100, true}, {69, true}}), record_of(three_uavs(), 100), "m.json");
  ASSERT_TRUE(m.shortfall.has_value());
  EXPECT_EQ(m.exit_code(), 8);
  EXPECT_EQ(*m.shortfall,
            "this run did not fly the swarm asked for: the UAVs nobody killed flew 269 of the 300 UAV ticks asked "
            "for (89.7 %, under the 90 % a run must fly) (exit 8, docs/exit-codes.md)");
  // The ticks asked come from the plan, not from the ticks reached: asked
  // 200, the same flight is half of it.
  m = merge_metrics(flown({{100, true}, {100, true}, {100, true}}), record_of(three_uavs(), 200), "m.json");
  ASSERT_TRUE(m.shortfall.has_value());
  EXPECT_NE(m.shortfall->find("flew 300 of the 600 UAV ticks asked for (50.0 %"), std::string::npos) << *m.shortfall;
  EXPECT_EQ(m.metrics["uav_ticks_asked"], 600);
  // Without a plan (another host's share) nothing is judged.
  EXPECT_FALSE(merge_metrics(flown({{1, false}}), record_of(three_uavs()), "m.json").shortfall.has_value());
  // A crash still says 1: the worse verdict.
  auto ps = three_uavs();
  ps[1].exit_code = 4;
  EXPECT_EQ(merge_metrics(flown({{100, true}, {100, true}, {69, true}}), record_of(ps, 100), "m.json").exit_code(), 1);
}

TEST(MetricsMerge, AUavThatDidNotFinishFailsTheRunUnlessItWasKilledOnPurpose) {
  auto ps = three_uavs();
  MergedMetrics m = merge_metrics(flown({{100, true}, {95, false}, {100, true}}), record_of(ps, 100), "m.json");
  ASSERT_TRUE(m.shortfall.has_value());
  EXPECT_EQ(m.exit_code(), 8);
  EXPECT_NE(m.shortfall->find("uav 1 did not finish and nobody killed it"), std::string::npos) << *m.shortfall;
  // Heard at the last tick, it flew every tick, whether or not its finished
  // state arrived before the end.
  m = merge_metrics(flown({{100, true}, {100, false}, {100, true}}), record_of(ps, 100), "m.json");
  EXPECT_FALSE(m.shortfall.has_value()) << *m.shortfall;
  // Killed on purpose: neither its ticks nor its end count against the run.
  ps[3].killed_on_purpose = true;  // uav-2 (ps[0] is the ground station)
  ps[3].term_signal = SIGKILL;
  m = merge_metrics(flown({{100, true}, {100, true}, {10, false}}), record_of(ps, 100), "m.json");
  EXPECT_FALSE(m.shortfall.has_value()) << *m.shortfall;
  EXPECT_EQ(m.exit_code(), 0);
}

TEST(MetricsMerge, AFailedRunsLastLineNamesTheProcessItsCodeAndItsLogsFirstError) {
  const std::string log = ::testing::TempDir() + "/phm-ground-" + std::to_string(::getpid()) + ".log";
  std::ofstream(log) << "01:02:03.456 info  [ground] conducting 100 lockstep ticks\n"
                     << "01:02:04.000 warning [ground] uav 0's state of tick 0 refused as implausible\n"
                     << "01:03:04.789 error [ground] lockstep tick 1 uav phase: 5 process(es) did not finish within 60 s\n"
                     << "01:03:05.000 critical [ground] fatal: second\n";
  ChildProcess c = ended("ground", "ground", 6);
  c.pid = 4242;
  EXPECT_EQ(failure_line(c, log),
            "the run failed: ground (pid 4242) exited with 6; its log's first error: lockstep tick 1 uav phase: 5 "
            "process(es) did not finish within 60 s (" +
                log + ")");
  // Colour codes around the level (a log written to a terminal first).
  std::ofstream(log) << "01:02:03.456 \x1b[31merror\x1b[m [uav-3] no view\n";
  EXPECT_EQ(first_error_line(log), std::optional<std::string>("no view"));
  std::ofstream(log) << "01:02:03.456 info  [uav-3] fine\n";
  EXPECT_FALSE(first_error_line(log).has_value());
  EXPECT_NE(failure_line(c, log).find("its log has no error line"), std::string::npos);
  std::remove(log.c_str());
}

TEST(MetricsMerge, AProcessKilledByASignalNobodySentFailsTheRun) {
  std::vector<ChildProcess> ps{ended("ground", "ground", 0), ended("uav-0", "uav", -1, SIGKILL)};
  const MergedMetrics m = merge_metrics(ground_metrics(), record_of(ps), "out/metrics.json");
  EXPECT_EQ(m.exit_code(), 1);
  EXPECT_EQ(m.crashed, 1U);
  EXPECT_EQ(m.killed, 0U);
  EXPECT_EQ(m.metrics["processes"][1]["crashed"], true);
  EXPECT_EQ(m.metrics["processes"][1]["status"], std::string("killed by ") + strsignal(SIGKILL));
}

TEST(MetricsMerge, AProcessSigkilledAfterIgnoringSigtermIsReportedAsSuchNotAsACrash) {
  // Under load UAVs that had not stopped 10 s after SIGTERM were SIGKILLed
  // and counted "crashed", like a real crash (issue 28).
  std::vector<ChildProcess> ps{ended("ground", "ground", 0), ended("uav-0", "uav", -1, SIGKILL),
                               ended("uav-1", "uav", -1, SIGKILL)};
  ps[1].killed_after_sigterm_s = 10;  // the stop's SIGKILL
  EXPECT_FALSE(ps[1].crashed());
  EXPECT_TRUE(ps[1].killed_at_stop());
  EXPECT_EQ(ps[1].describe(), std::string("killed by ") + strsignal(SIGKILL) + " after ignoring SIGTERM for 10 s");
  EXPECT_TRUE(ps[2].crashed()) << "a SIGKILL nobody sent is still a crash";
  EXPECT_FALSE(ps[2].killed_at_stop());
  const MergedMetrics m = merge_metrics(ground_metrics(), record_of(ps), "out/metrics.json");
  EXPECT_EQ(m.metrics["processes_killed_at_stop"], 1);
  EXPECT_EQ(m.metrics["processes_crashed"], 1);
  EXPECT_EQ(m.metrics["processes"][1]["killed_at_stop"], true);
  EXPECT_EQ(m.metrics["processes"][1]["crashed"], false);
  EXPECT_EQ(m.exit_code(), 1) << "uav-1 crashed";
  ps.pop_back();
  EXPECT_EQ(merge_metrics(ground_metrics(), record_of(ps), "out/metrics.json").exit_code(), 0)
      << "a process slow to stop is reported, not a failed run";
}

TEST(MetricsMerge, AProcessEndedByTheStopsSigtermOrByCtrlCIsStoppedNotCrashed) {
  // Stopped milliseconds after their start, 13 of 17 secure Cyclone
  // processes died of the launcher's SIGTERM before they installed their
  // handlers, and counted as crashed (issue 42).
  std::vector<ChildProcess> ps{ended("ground", "ground", 0), ended("uav-0", "uav", -1, SIGTERM),
                               ended("uav-1", "uav", -1, SIGINT), ended("uav-2", "uav", -1, SIGTERM),
                               ended("uav-3", "uav", -1, SIGSEGV)};
  ps[1].asked_to_stop = true;
  ps[4].asked_to_stop = true;
  EXPECT_FALSE(ps[1].crashed());
  EXPECT_EQ(ps[1].describe(), "stopped by the launcher's SIGTERM before it handled signals");
  EXPECT_FALSE(ps[2].crashed());
  EXPECT_EQ(ps[2].describe(), "stopped by Interrupt (Ctrl-C)");
  EXPECT_TRUE(ps[3].crashed()) << "a SIGTERM the launcher did not send";
  EXPECT_TRUE(ps[4].crashed()) << "a segmentation fault while stopping is a crash";
  const MergedMetrics m = merge_metrics(ground_metrics(), record_of(ps), "out/metrics.json");
  EXPECT_EQ(m.metrics["processes_crashed"], 2);
  ps.pop_back();
  ps.pop_back();
  EXPECT_EQ(merge_metrics(ground_metrics(), record_of(ps), "out/metrics.json").metrics["processes_crashed"], 0);
}

TEST(MetricsMerge, AProcessThatExitedWithAnErrorFailsTheRunAndOneAskedToStopDoesNot) {
  std::vector<ChildProcess> ps{ended("ground", "ground", 0), ended("place-1", "place", 4)};
  EXPECT_EQ(merge_metrics(ground_metrics(), record_of(ps, 100), "m.json").exit_code(), 1);
  ps[1].exit_code = 0;
  ps[1].asked_to_stop = true;
  EXPECT_EQ(merge_metrics(ground_metrics(), record_of(ps, 100), "m.json").exit_code(), 0);
}

TEST(MetricsMerge, AMissingGroundStationFileFailsTheRunOnlyOnTheGroundStationsHost) {
  const std::vector<ChildProcess> ps{ended("uav-1", "uav", 0)};
  RunRecord r = record_of(ps);
  const MergedMetrics here = merge_metrics(nullptr, r, "out/metrics.json");
  EXPECT_EQ(here.exit_code(), 1);
  EXPECT_EQ(here.errors, (std::vector<std::string>{"the ground station left no out/metrics.json"}));

  r.share = {3, 1, 0};
  EXPECT_EQ(metrics_path("out", r.share), "out/host-1.json");
  EXPECT_EQ(metrics_path("out", {3, 0, 0}), "out/metrics.json");
  const MergedMetrics elsewhere = merge_metrics(nullptr, r, "out/host-1.json");
  EXPECT_EQ(elsewhere.exit_code(), 0);
  EXPECT_EQ(elsewhere.metrics["hosts"], 3);
  EXPECT_EQ(elsewhere.metrics["host_index"], 1);
  EXPECT_EQ(elsewhere.metrics["ground_host"], 0);
}

TEST(MetricsMerge, AFaultThatCouldNotBeInjectedFailsTheRun) {
  const std::vector<ChildProcess> ps{ended("ground", "ground", 0)};
  RunRecord r = record_of(ps);
  r.faults["faults_failed"] = 2;
  r.fault_failures = 2;
  const MergedMetrics m = merge_metrics(ground_metrics(), r, "m.json");
  EXPECT_EQ(m.exit_code(), 1);
  EXPECT_EQ(m.errors, (std::vector<std::string>{"2 fault events could not be injected (metrics.json \"faults\")"}));
  EXPECT_EQ(m.metrics["faults_failed"], 2);
}

TEST(MetricsMerge, ResourcesSumCpuPerRoleAndAverageTheSampledProcesses) {
  std::vector<ChildProcess> ps{ended("uav-0", "uav", 0), ended("uav-1", "uav", 0), ended("place-0", "place", 0)};
  ps[0].cpu_user_s = 1.5;
  ps[1].cpu_user_s = 0.25;
  ps[0].max_rss_mib = 30;
  ps[1].max_rss_mib = 50;
  ps[0].sample = ProcessSample{10.0, 20.0, 12U};
  ps[1].sample = ProcessSample{20.0, 40.0, 14U};
  RunRecord r = record_of(ps);
  r.udp_start = UdpCounters{100, 200};
  r.udp_end = UdpCounters{150, 260};
  r.wall_s = 6.12345;
  const MergedMetrics m = merge_metrics(ground_metrics(), r, "m.json");
  const nlohmann::json& uav = m.metrics["resources"]["uav"];
  EXPECT_EQ(uav["count"], 2);
  EXPECT_DOUBLE_EQ(uav["cpu_user_s"].get<double>(), 1.75);
  EXPECT_DOUBLE_EQ(uav["pss_mib_mean"].get<double>(), 15.0);
  EXPECT_DOUBLE_EQ(uav["pss_mib_max"].get<double>(), 20.0);
  EXPECT_DOUBLE_EQ(uav["rss_mib_mean"].get<double>(), 30.0);
  EXPECT_DOUBLE_EQ(uav["threads_mean"].get<double>(), 13.0);
  EXPECT_DOUBLE_EQ(uav["max_rss_mib_mean"].get<double>(), 40.0);
  EXPECT_EQ(m.metrics["resources"]["place"]["sampled"], 0);
  EXPECT_TRUE(m.metrics["resources"]["place"]["pss_mib_mean"].is_null());
  EXPECT_EQ(m.metrics["resources"]["ground"]["count"], 0);
  EXPECT_EQ(m.metrics["udp_in_datagrams"], 50);
  EXPECT_EQ(m.metrics["udp_out_datagrams"], 60);
  EXPECT_DOUBLE_EQ(m.metrics["wall_s"].get<double>(), 6.123);
  // Counters that went backwards (another namespace, a reset) are no figure.
  r.udp_end = UdpCounters{90, 260};
  EXPECT_TRUE(merge_metrics(ground_metrics(), r, "m.json").metrics["udp_in_datagrams"].is_null());
}

TEST(MetricsMerge, TheSteadyWindowGivesCpuContextSwitchesThreadsAndDatagramsPerUavTickDue) {
  std::vector<ChildProcess> ps{ended("uav-0", "uav", 0), ended("uav-1", "uav", 0), ended("place-0", "place", 0),
                               ended("uav-2", "uav", 0)};
  // Two UAVs and a place agent seen at both ends of a 2 s window at 5 Hz:
  // 2 x 5 x 2 = 20 UAV ticks due. uav-2 was seen only at the start (it
  // ended inside the window) and counts for nothing.
  ps[0].window_cpu[0] = CpuSample{1'000'000, 10, 1, {{"recv", 400'000}, {"tev", 600'000}}};
  ps[0].window_cpu[1] = CpuSample{5'000'000, 30, 3, {{"recv", 2'400'000}, {"tev", 2'600'000}}};
  ps[1].window_cpu[0] = CpuSample{0, 0, 0, {{"recv", 0}}};
  ps[1].window_cpu[1] = CpuSample{2'000'000, 20, 1, {{"recv", 2'000'000}}};
  ps[2].window_cpu[0] = CpuSample{10'000'000, 100, 10, {{"recv", 10'000'000}}};
  ps[2].window_cpu[1] = CpuSample{30'000'000, 120, 50, {{"recv", 30'000'000}}};
  ps[3].window_cpu[0] = CpuSample{1'000'000, 0, 0, {}};
  RunRecord r = record_of(ps);
  r.steady = SteadyWindow{2.0, 5.0, UdpCounters{1000, 0}, UdpCounters{1300, 0}};
  const nlohmann::json s = merge_metrics(ground_metrics(), r, "m.json").metrics["steady"];
  ASSERT_TRUE(s.is_object());
  EXPECT_EQ(s["uavs"], 2);
  EXPECT_DOUBLE_EQ(s["uav_ticks"].get<double>(), 20.0);
  // UAVs: 4 ms + 2 ms over 20 ticks; the place agent 20 ms over 20.
  EXPECT_DOUBLE_EQ(s["cpu_ms_per_uav_tick"]["uav"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(s["cpu_ms_per_uav_tick"]["place"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(s["cpu_ms_per_uav_tick"]["all"].get<double>(), 1.3);
  EXPECT_FALSE(s["cpu_ms_per_uav_tick"].contains("ground"));
  EXPECT_DOUBLE_EQ(s["ctx_voluntary_per_uav_tick"]["all"].get<double>(), 3.0);        // (20 + 20 + 20) / 20
  EXPECT_DOUBLE_EQ(s["ctx_involuntary_per_uav_tick"]["place"].get<double>(), 2.0);    // 40 / 20
  EXPECT_DOUBLE_EQ(s["threads_cpu_ms_per_uav_tick"]["uav/recv"].get<double>(), 0.2);  // (2 + 2) ms / 20
  EXPECT_DOUBLE_EQ(s["threads_cpu_ms_per_uav_tick"]["uav/tev"].get<double>(), 0.1);
  EXPECT_DOUBLE_EQ(s["udp_in_per_uav_tick"].get<double>(), 15.0);  // 300 / 20
  // No window (lockstep, or the flight ended before it closed): left out.
  r.steady.reset();
  EXPECT_FALSE(merge_metrics(ground_metrics(), r, "m.json").metrics.contains("steady"));
}

TEST(MetricsMerge, TheSteadyWindowsUavsWhoseThreadsWereReadStandForAllUavs) {
  // Four UAVs at both ends of a 1 s window at 5 Hz (20 UAV ticks due); the
  // threads of two were read, of the other two only the process's time.
  std::vector<ChildProcess> ps{ended("uav-0", "uav", 0), ended("uav-1", "uav", 0), ended("uav-2", "uav", 0),
                               ended("uav-3", "uav", 0), ended("place-0", "place", 0)};
  ps[0].window_cpu[0] = CpuSample{0, 0, 0, {{"recv", 0}, {"pheromesh-uav", 0}}};
  ps[0].window_cpu[1] = CpuSample{3'000'000, 0, 0, {{"recv", 1'000'000}, {"pheromesh-uav", 2'000'000}}};
  ps[1].window_cpu[0] = CpuSample{0, 0, 0, {{"recv", 0}, {"pheromesh-uav", 0}}};
  ps[1].window_cpu[1] = CpuSample{1'000'000, 0, 0, {{"recv", 1'000'000}, {"pheromesh-uav", 0}}};
  for (int i : {2, 3}) {
    ps[i].window_cpu[0] = CpuSample{10'000'000, 0, 0, {}, false};
    ps[i].window_cpu[1] = CpuSample{20'000'000, 0, 0, {}, false};
  }
  ps[4].window_cpu[0] = CpuSample{0, 0, 0, {{"recv", 0}}};
  ps[4].window_cpu[1] = CpuSample{4'000'000, 0, 0, {{"recv", 4'000'000}}};
  RunRecord r = record_of(ps);
  r.steady = SteadyWindow{1.0, 5.0, std::nullopt, std::nullopt};
  const nlohmann::json s = merge_metrics(ground_metrics(), r, "m.json").metrics["steady"];
  ASSERT_TRUE(s.is_object());
  EXPECT_EQ(s["uavs"], 4);
  EXPECT_EQ(s["uavs_threads_read"], 2);
  // The UAVs' CPU counts every UAV: 3 + 1 + 10 + 10 ms over 20 ticks.
  EXPECT_DOUBLE_EQ(s["cpu_ms_per_uav_tick"]["uav"].get<double>(), 1.2);
  // Their threads: the two read, times 4 / 2. recv (1 + 1) x 2 = 4 ms,
  // the main thread (2 + 0) x 2 = 4 ms, each over 20 ticks.
  EXPECT_DOUBLE_EQ(s["threads_cpu_ms_per_uav_tick"]["uav/recv"].get<double>(), 0.2);
  EXPECT_DOUBLE_EQ(s["threads_cpu_ms_per_uav_tick"]["uav/pheromesh-uav"].get<double>(), 0.2);
  // The place agent's threads are all read and not scaled: 4 ms / 20.
  EXPECT_DOUBLE_EQ(s["threads_cpu_ms_per_uav_tick"]["place/recv"].get<double>(), 0.2);
}

// What `pheromesh run` writes: a ground station's metrics (from a
// simulated recorder, through the function the ground station calls) merged
// with the launcher's processes, faults and resources.
TEST(MetricsMerge, AMergedRunsMetricsConformToTheSchemaInTheRepository) {
  auto s = core::load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto");
  ASSERT_TRUE(s.ok());
  core::ScenarioConfig c = s.value();
  c.ticks = 20;
  core::Simulator sim(c);
  sim.run();
  const report::RunInfo info{"cyclone", "realtime", report::Runner::Processes, c.uavs, 2.5, {}, {}, uint64_t{1000}};
  std::vector<ChildProcess> ps{ended("ground", "ground", 0), ended("uav-0", "uav", 0), ended("place-0", "place", 0)};
  RunRecord r = record_of(ps);
  r.wall_s = 3.0;
  const MergedMetrics m = merge_metrics(report::metrics_json(sim.recorder(), info), r, "m.json");
  std::ifstream in(std::string(PHEROMESH_SOURCE_DIR) + "/docs/schema/metrics.schema.json");
  std::stringstream schema;
  schema << in.rdbuf();
  const auto errors = test::SchemaSubset(nlohmann::json::parse(schema.str())).check(m.metrics);
  std::string all;
  for (const auto& e : errors) all += e + "\n";
  EXPECT_EQ(all, "");
}

}  // namespace
}  // namespace pheromesh::cli
