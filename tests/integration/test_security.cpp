// DDS Security (docs/security.md): real processes with identities of
// `pheromesh security init`, per vendor. Domains 90-93. A mixed swarm cannot
// be secured (the vendors' handshakes do not interoperate): under
// PHEROMESH_DDS=mixed the tests check that `pheromesh run` says so.
#include <csignal>

#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers

namespace {

std::string backend() {
  const char* v = std::getenv("PHEROMESH_DDS");
  return v != nullptr && *v != '\0' ? v : "cyclone";
}

// `pheromesh security init` into OUT/sec for small-test.
std::string init_security(const std::string& out, const std::string& extra = "") {
  const std::string dir = out + "/sec";
  const Output o = run(kBin + "/pheromesh security init " + dir + " --scenario " + kSrc +
                       "/scenarios/small-test.textproto " + extra);
  EXPECT_EQ(o.exit_code, 0) << o.text;
  return dir;
}

// The probes and the swarms here discover by unicast on loopback
// (onehost-unicast): they read every process, as a flat profile does, and
// DDS Security over Fast DDS needs unicast discovery
// (bus::check_secure_profile).
constexpr const char* kProfile = "onehost-unicast";

std::vector<std::string> probe(const std::string& vendor, int domain, const std::vector<std::string>& args) {
  std::vector<std::string> v{kBin + "/pheromesh-test-probe", "--dds",         vendor,  "--domain",
                             std::to_string(domain),         "--dds-profile", kProfile};
  v.insert(v.end(), args.begin(), args.end());
  return v;
}

std::string command(const std::vector<std::string>& args) {
  std::string s;
  for (const auto& a : args) s += (s.empty() ? "" : " ") + a;
  return s;
}

// The numbers of a snoop's summary line ("snooped N samples: tiles T ...").
struct Snooped {
  long total = -1, tiles = -1, clocks = -1, matched = -1;
};
Snooped parse_snoop(const std::string& text) {
  Snooped s;
  const auto at = text.find("snooped ");
  if (at == std::string::npos) return s;
  const std::string line = text.substr(at, text.find('\n', at) - at);
  auto number_after = [&](const std::string& key) -> long {
    const auto k = line.find(key);
    return k == std::string::npos ? -1 : std::stol(line.substr(k + key.size()));
  };
  s.total = number_after("snooped ");
  s.tiles = number_after("tiles ");
  s.clocks = number_after("clocks ");
  s.matched = number_after("most readers matched ");
  return s;
}

}  // namespace

TEST(Security, ASecureSwarmRunsToItsEndWhileAnUnauthenticatedParticipantReadsNothingAndInjectsNothing) {
  const std::string out = out_dir("security-swarm");
  const int domain = 90;
  const std::string sec = init_security(out);
  if (backend() == "mixed") {
    const Output o = run(pheromesh_run("small-test.textproto", out + "/run", domain, "--secure " + sec + " --ticks 10"));
    EXPECT_EQ(o.exit_code, 2) << o.text;
    EXPECT_NE(o.text.find("do not interoperate"), std::string::npos) << o.text;
    return;
  }
  const std::string vendor = backend();
  // Both snoops read every topic and try to write deposits into region 0
  // from the start of the swarm to its end: one without identity, one with
  // the read-only monitor identity (the guard: it must read).
  const Background open_snoop = start(probe(vendor, domain, {"snoop", "--seconds", "300"}), out + "/open-snoop.txt");
  const Background monitor_snoop =
      start(probe(vendor, domain, {"--secure", sec, "--identity", "monitor", "snoop", "--seconds", "300"}),
            out + "/monitor-snoop.txt");
  const Output o = run(pheromesh_run(
      "small-test.textproto", out + "/run", domain,
      "--secure " + sec + " --dds " + vendor + " --uavs 4 --ticks 150 --rate 25 --dds-profile " + kProfile));
  kill(open_snoop.pid, SIGTERM);
  kill(monitor_snoop.pid, SIGTERM);
  EXPECT_EQ(wait_exit(open_snoop.pid, std::chrono::seconds(20)), 0);
  EXPECT_EQ(wait_exit(monitor_snoop.pid, std::chrono::seconds(20)), 0);
  // The whole swarm ran to its end on both vendors. On Fast DDS this once
  // failed in one run of several (a place agent and a UAV never joined),
  // under the multicast profile onehost: the vendor's race between its two
  // discovery threads (docs/security.md, "Fast DDS 2.9.1: one discovery
  // socket"). With unicast discovery, 5 runs of 5 here ran to their end.
  ASSERT_EQ(o.exit_code, 0) << o.text;
  const json m = read_metrics(out + "/run");
  ASSERT_FALSE(m.is_null()) << o.text;
  EXPECT_EQ(m["processes_crashed"], 0);
  EXPECT_EQ(m["place_agents_finished"], 4);
  expect_accounting(m);
  // The snoops' deposits (UAV 900001) would be refused (unknown UAV, or a
  // sequence number far ahead) or applied beyond what the UAVs sent.
  EXPECT_EQ(m["refused"]["unknown_uav"], 0) << m.dump(2);
  EXPECT_EQ(m["refused"]["seq_far_ahead"], 0) << m.dump(2);
  EXPECT_EQ(m["deposits_rejected"], 0) << m.dump(2);

  const std::string open_text = slurp(out + "/open-snoop.txt");
  const Snooped open = parse_snoop(open_text);
  EXPECT_EQ(open.total, 0) << open_text;
  EXPECT_EQ(open.matched, 0) << open_text;
  const std::string monitor_text = slurp(out + "/monitor-snoop.txt");
  const Snooped monitor = parse_snoop(monitor_text);
  EXPECT_GT(monitor.total, 100) << monitor_text;  // the same reader with an identity reads the swarm
  EXPECT_NE(monitor_text.find("deposit writer refused"), std::string::npos) << monitor_text;
}

// Issue 42 D6: secure processes stopped, as by Ctrl-C (SIGINT to the whole
// process group), while they start and authenticate one another, and again
// while they fly, end cleanly: none dies of a signal, none exits with an
// error, none has to be killed. Before, secure Fast DDS probes died during
// their discovery (an assertion in SecurityManager::discovered_participant,
// a segmentation fault in PDPSimple::assignRemoteEndpoints: two threads at
// once, docs/security.md "Fast DDS 2.9.1: one discovery socket"). 17 secure
// processes on the default profile (cells). Domain 94.
TEST(Security, SecureProcessesStoppedWhileTheyAuthenticateAndWhileTheyFlyEndCleanly) {
  if (backend() == "mixed") GTEST_SKIP() << "a mixed swarm cannot be secure (the swarm test checks the refusal)";
  const std::string out = out_dir("security-stop");
  const std::string sec = init_security(out, "--uavs 12");
  if (backend() == "fastdds") {
    // The race's cause, discovery by multicast and unicast at once, is refused.
    const Output flat = run(pheromesh_run("small-test.textproto", out + "/flat", 94,
                                          "--secure " + sec + " --uavs 12 --dds-profile onehost --ticks 5"));
    EXPECT_EQ(flat.exit_code, 2) << flat.text;
    EXPECT_NE(flat.text.find("--secure over Fast DDS needs unicast discovery"), std::string::npos) << flat.text;
  }
  // When to stop: the ground station started (the others are being started
  // and authenticate), or the swarm was discovered and flies.
  for (const auto& [name, line] : {std::pair<std::string, std::string>{"starting", "[ground] ground station on domain"},
                                   {"flying", "discovery complete"}}) {
    const std::string run_out = out + "/" + name;
    const Background b =
        start_run("small-test.textproto", run_out, 94, "--secure " + sec + " --uavs 12 --ticks 100000 --rate 5");
    ASSERT_TRUE(wait_for_text(run_out + ".txt", line, std::chrono::seconds(120))) << name << "\n"
                                                                                  << slurp(run_out + ".txt");
    kill(-b.pid, SIGINT);
    EXPECT_EQ(wait_exit(b.pid, std::chrono::seconds(90)), 130) << name << "\n" << slurp(run_out + ".txt");
    const json m = read_metrics(run_out);
    ASSERT_FALSE(m.is_null()) << name << "\n" << slurp(run_out + ".txt");
    EXPECT_EQ(m["processes_crashed"], 0) << name;
    // Stopped while it starts them, the launcher may not have started every
    // UAV yet; the ground station and the place agents come first.
    if (name == "flying") {
      EXPECT_EQ(m["processes"].size(), 17U) << "the ground station, 4 place agents, 12 uavs";
    } else {
      EXPECT_GE(m["processes"].size(), 5U);
    }
    // Each exited 0, or died of the stop's own signal before it had
    // installed its handlers: the launcher's SIGTERM (Cyclone, stopped
    // milliseconds after its start), or the Ctrl-C itself, held by the
    // launcher while it forked the process and let through at its default
    // action (launch/child_spawn.hpp, StopSignalsHeld; before, the launcher's
    // handler swallowed it in the child, which then ran on until SIGKILLed):
    // no segmentation fault, no abort, no SIGKILL.
    for (const auto& p : m["processes"]) {
      const std::string status = p["status"];
      EXPECT_TRUE(status == "exited with 0" ||
                  status == "stopped by the launcher's SIGTERM before it handled signals" ||
                  status == "stopped by Interrupt (Ctrl-C)")
          << name << ": " << p.dump() << "\n"
          << slurp(run_out + ".txt");
      EXPECT_EQ(p["crashed"], false) << name << ": " << p.dump();
    }
  }
}

namespace {

// `offender` tries to write `topic`; `allowed` (the guard) writes it too.
// A monitor reads every topic meanwhile: it must get the allowed sample and
// only that one.
void expect_only_the_allowed_identity_writes(const std::string& name, int domain, const std::string& topic,
                                             const std::string& offender, const std::string& allowed) {
  // Secure participants of the two vendors never authenticate each other:
  // each vendor is checked on its own backend.
  if (backend() == "mixed") GTEST_SKIP() << "no secure mixed swarms (docs/security.md)";
  const std::string out = out_dir(name);
  const std::string sec = init_security(out);
  const std::string vendor = backend();
  const bool is_tile = topic == "tile";
  const Background monitor = start(probe(vendor, domain,
                                         {"--secure", sec, "--identity", "monitor", "snoop", "--seconds", "90",
                                          is_tile ? "--until-tiles" : "--until-clocks", "1"}),
                                   out + "/monitor.txt");
  const Output refused = run(command(
      probe(vendor, domain, {"--secure", sec, "--identity", offender, "offend", "--topic", topic, "--linger", "5"})));
  EXPECT_EQ(refused.exit_code, 0) << refused.text;
  EXPECT_NE(refused.text.find("refused: "), std::string::npos) << refused.text;
  EXPECT_EQ(refused.text.find(topic + " written"), std::string::npos) << refused.text;
  // The guard stays until the monitor has read its sample (or 60 s).
  const Background guard = start(
      probe(vendor, domain, {"--secure", sec, "--identity", allowed, "offend", "--topic", topic, "--linger", "60"}),
      out + "/guard.txt");
  EXPECT_EQ(wait_exit(monitor.pid, std::chrono::seconds(120)), 0);
  kill(guard.pid, SIGTERM);
  EXPECT_EQ(wait_exit(guard.pid, std::chrono::seconds(20)), 0);
  EXPECT_NE(slurp(out + "/guard.txt").find(topic + " written"), std::string::npos) << slurp(out + "/guard.txt");
  const std::string text = slurp(out + "/monitor.txt");
  const Snooped s = parse_snoop(text);
  EXPECT_EQ(is_tile ? s.tiles : s.clocks, 1) << text;  // the guard's, and nothing of the offender
}

}  // namespace

TEST(Security, AUavIdentityCannotPublishATile) {
  expect_only_the_allowed_identity_writes("security-uav-tile", 91, "tile", "uav-0", "place-0");
}

TEST(Security, APlaceAgentIdentityCannotDriveTheClock) {
  expect_only_the_allowed_identity_writes("security-place-clock", 92, "clock", "place-0", "ground");
}

TEST(Cli, ASecureRunWithoutAProcessIdentityNamesTheMissingFileAndTheCommandThatMakesIt) {
  const std::string out = out_dir("security-missing");
  // Identities for 2 UAVs; the run asks for 4.
  const std::string sec = init_security(out, "--uavs 2");
  const Output o = run(pheromesh_run("small-test.textproto", out + "/run", 93,
                                     "--secure " + sec + " --dds cyclone --uavs 4 --ticks 10"));
  EXPECT_EQ(o.exit_code, 2) << o.text;
  EXPECT_NE(o.text.find(sec + "/uav-2/cert.pem is missing"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("pheromesh security init " + sec), std::string::npos) << o.text;
  // A process started by hand says the same and starts nothing.
  const Output uav =
      run(kBin + "/pheromesh-uav --scenario " + kSrc + "/scenarios/small-test.textproto --id 3 --uavs 4 " +
          "--domain 93 --dds-profile " + kProfile + " --secure " + sec);
  EXPECT_EQ(uav.exit_code, 3) << uav.text;
  EXPECT_NE(uav.text.find("uav-3/cert.pem is missing"), std::string::npos) << uav.text;
  // And an existing directory is not overwritten without --force.
  const Output again = run(kBin + "/pheromesh security init " + sec + " --uavs 2 --regions 4");
  EXPECT_EQ(again.exit_code, 2) << again.text;
  EXPECT_NE(again.text.find("--force"), std::string::npos) << again.text;
  EXPECT_EQ(run(kBin + "/pheromesh security init " + sec + " --uavs 4 --regions 4 --force").exit_code, 0);
  EXPECT_TRUE(fs::exists(sec + "/uav-3/key.pem"));
  EXPECT_EQ(fs::status(sec + "/uav-3/key.pem").permissions() & (fs::perms::group_all | fs::perms::others_all),
            fs::perms::none);
}
