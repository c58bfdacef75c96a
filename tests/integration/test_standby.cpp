// Hot-standby place agents and honest deposit accounting, with real
// processes and real signals (docs/faults.md). Domains 41-44.
#include <set>

#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers

namespace {

// The pid of a process of the run on `domain` whose command line holds `exe` and `what`.
pid_t find_process(const std::string& exe, int domain, const std::string& what) {
  const auto deadline = Clock::now() + std::chrono::seconds(30);
  while (Clock::now() < deadline) {
    for (const auto& e : fs::directory_iterator("/proc")) {
      const std::string name = e.path().filename();
      if (name.find_first_not_of("0123456789") != std::string::npos) continue;
      std::string cmd = slurp(e.path().string() + "/cmdline");
      std::replace(cmd.begin(), cmd.end(), '\0', ' ');
      cmd += " ";
      if (cmd.find(exe) != std::string::npos && cmd.find("--domain " + std::to_string(domain) + " ") != std::string::npos &&
          cmd.find(what) != std::string::npos) {
        return std::stoi(name);
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return -1;
}

}  // namespace

// Killing two primaries in the middle of a lockstep run changes nothing:
// their standbys were in step and take over; the metrics and the final
// field are the simulator's, byte for byte. On every vendor set, also all
// Fast DDS (shared ownership: each replica's halo ring is an instance of its
// own, docs/faults.md "Hot-standby place agents").
TEST(Standby, KillingPrimariesInLockstepGivesTheSimulatorsNumbersAndField) {
  // Kills between ticks (the launcher kills and reaps them before the
  // conductor announces the tick): the simulator with the same schedule and
  // --standby is the simulator without faults.
  expect_lockstep_matches_sim("small-test.textproto",
                              "--ticks 400 --standby --faults \"kill place:0 @120t; kill place:3 @250t\"", 41,
                              "standby-lockstep");
  const json m = read_metrics(out_path("standby-lockstep-lockstep"));
  ASSERT_FALSE(m.is_null());
  EXPECT_EQ(m["processes_killed"], 2) << "both kills happened while the run went on";
  EXPECT_EQ(m["deposits_lost"], 0);
  EXPECT_EQ(m["place_replicas"]["place-0"]["lost"], true);
  EXPECT_EQ(m["place_replicas"]["place-0.r1"]["finished"], true);
  EXPECT_EQ(m["place_replicas"]["place-3.r1"]["finished"], true);
}

// Realtime: the standby received every deposit its primary did, so killing
// the primary loses none: what the UAVs sent is what was applied.
TEST(Standby, KillingAPrimaryInRealtimeLosesNoDeposit) {
  const std::string out = out_dir("standby-realtime");
  const Output o = run(pheromesh_run("small-test.textproto", out, 42, "--duration 8 --standby --kill place:0@3s"));
  ASSERT_EQ(o.exit_code, 0) << o.text;
  const json m = read_metrics(out);
  ASSERT_FALSE(m.is_null()) << o.text;
  expect_accounting(m);
  EXPECT_EQ(m["deposits_lost"], 0) << m.dump(2);
  EXPECT_EQ(m["deposits_unconfirmed_by_uavs"], 0) << "every UAV's home (a replica of it) confirmed every deposit";
  EXPECT_GT(m["deposits_duplicate_dropped"].get<uint64_t>(), 0U) << "both replicas of a home forward; the owners drop the copy";
  EXPECT_EQ(m["place_replicas"]["place-0"]["lost"], true);
  EXPECT_EQ(m["place_replicas"]["place-0.r1"]["finished"], true);
  EXPECT_NE(o.text.find("place agent 0 lost (liveliness); region 0 is served by standby 1"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("places 4/4 (1 on standby)"), std::string::npos) << o.text;
}

// Without a standby, the deposits a dead place agent never received are
// counted lost: by the ground station (sent = applied + rejected + lost) and
// by the UAVs its home served (never confirmed).
TEST(Faults, APlaceAgentKilledWithoutStandbyHasItsDepositsCountedLostAndItsUavReachesItsBackup) {
  const std::string out = out_dir("faults-place-lost");
  // Killed after the start gate (the swarm flies about 12 s). In cells a
  // realtime UAV names its backup gateway only once its home is gone
  // (Transport::reach_reserve): UAV 0, homed on region 0, then discovers
  // place agent 1 and flies on through it.
  const Output o =
      run(pheromesh_run("small-test.textproto", out, 43, "--duration 12 --kill place:0@5s --dds-profile cells"));
  ASSERT_EQ(o.exit_code, 0) << o.text;
  const json m = read_metrics(out);
  ASSERT_FALSE(m.is_null()) << o.text;
  const std::string uav0 = slurp(out + "/logs/uav-0.log");
  EXPECT_NE(uav0.find("naming place agent 1 in discovery now"), std::string::npos) << uav0;
  // Its states reach the ground station through the backup to the end, as
  // the other UAVs' do through their homes (without the backup they stop at
  // the kill, about 7 s before the end).
  uint32_t last = 0;
  for (const auto& [id, u] : m["uav_status"].items()) last = std::max(last, u["last_tick"].get<uint32_t>());
  EXPECT_GT(m["uav_status"]["0"]["last_tick"].get<uint32_t>(), last * 8 / 10) << m["uav_status"].dump(2);
  const auto sent = m["deposits_sent"].get<uint64_t>();
  const auto lost = m["deposits_lost"].get<uint64_t>();
  const auto rejected = m["deposits_rejected"].get<uint64_t>();
  // Lost in transit, or refused with a reason by a home that could not forward them.
  EXPECT_GT(lost + rejected, 0U) << m.dump(2);
  EXPECT_EQ(sent, m["deposits_applied"].get<uint64_t>() + rejected + lost);
  EXPECT_GT(m["deposits_unconfirmed_by_uavs"].get<uint64_t>(), 0U) << "uav-0, homed on region 0, saw them unconfirmed";
  EXPECT_NE(o.text.find("region 0 has no live place agent"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("places 3/4"), std::string::npos) << o.text;
}

// A place agent stopped (SIGSTOP) longer than its lease is reported lost,
// and alive again once it continues (SIGCONT).
TEST(Faults, AStoppedPlaceAgentIsShownAliveAgainWhenItResumes) {
  const std::string out = out_dir("faults-place-stop");
  const int domain = 44;
  const Background launcher = start_run("small-test.textproto", out, domain, "--duration 10");
  const pid_t victim = find_process("pheromesh-place", domain, "--region 1 ");
  ASSERT_GT(victim, 0);
  ASSERT_TRUE(wait_for_text(launcher.out_path, "places 4/4", std::chrono::seconds(30))) << slurp(launcher.out_path);
  ASSERT_EQ(kill(victim, SIGSTOP), 0);
  // Resumed as soon as it is reported lost: its lease ran out, which is all
  // the test asks of the stop.
  const bool lost = wait_for_text(launcher.out_path, "place agent 1 lost", std::chrono::seconds(10));
  ASSERT_EQ(kill(victim, SIGCONT), 0);
  const bool back = wait_for_text(launcher.out_path, "place agent 1 is back", std::chrono::seconds(10));
  const int rc = wait_exit(launcher.pid, std::chrono::seconds(90));
  const std::string text = slurp(launcher.out_path);
  EXPECT_TRUE(lost) << text;
  EXPECT_TRUE(back) << text;
  EXPECT_EQ(rc, 0) << text;
  const json m = read_metrics(out);
  ASSERT_FALSE(m.is_null()) << text;
  EXPECT_EQ(m["place_replicas"]["place-1"]["lost"], false) << "alive at the end";
  EXPECT_EQ(m["place_replicas"]["place-1"]["finished"], true);
  // In cells (the default) a UAV homed on region 1 names its backup when its
  // home falls silent, by making its participant again
  // (Transport::reach_reserve): what it had written to its home and not yet
  // had acknowledged goes with the old participant. Every such deposit is
  // counted lost (docs/faults.md, "In cells"); none disappears.
  EXPECT_EQ(m["deposits_sent"].get<uint64_t>(), m["deposits_applied"].get<uint64_t>() +
                                                    m["deposits_rejected"].get<uint64_t>() +
                                                    m["deposits_lost"].get<uint64_t>())
      << accounting_summary(m);
}
