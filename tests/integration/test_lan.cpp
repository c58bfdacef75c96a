// One swarm over several "hosts": network namespaces joined by a bridge,
// each with its own address, as LAN hosts are (docs/deployment.md). Every
// host runs `pheromesh run --hosts 3 --host-index I`; a monitor in a fourth
// namespace attaches mid-run with only the domain id (and in cells the hosts'
// addresses). Discovery in cells (the default, with multicast dropped on the
// bridge so that nothing else can work), by multicast (profile lan) and by
// unicast peers (lan-unicast, multicast dropped too); in cells also secure.
// Traffic stays in the namespaces this test makes. Domains 70-71, 74-77; needs root (ip netns).
#include <unistd.h>

#include <regex>

#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using nlohmann::json;

namespace {

constexpr int kHosts = 3;
const std::string kPrefix = "phlan";  // namespaces phlan-sw, phlan-h0 .. phlan-h3

std::string ns(int i) { return kPrefix + "-h" + std::to_string(i); }
std::string address(int i) { return "10.78.0." + std::to_string(i + 1); }

// Runs `cmd`; fails the test (with its output) if it does not exit 0.
void must(const std::string& cmd) {
  const Output o = run(cmd);
  ASSERT_EQ(o.exit_code, 0) << cmd << "\n" << o.text;
}

// A switch namespace with a bridge, and hosts 0..3, each with eth0 on it.
class LanNet {
 public:
  explicit LanNet(bool drop_multicast) {
    teardown();
    const std::string sw = kPrefix + "-sw";
    must("ip netns add " + sw);
    must("ip -n " + sw + " link add br0 type bridge mcast_snooping 0");
    must("ip -n " + sw + " link set br0 up");
    for (int i = 0; i <= kHosts; ++i) {
      must("ip netns add " + ns(i));
      must("ip -n " + sw + " link add p" + std::to_string(i) + " type veth peer name eth0 netns " + ns(i));
      must("ip -n " + sw + " link set p" + std::to_string(i) + " master br0 up");
      must("ip -n " + ns(i) + " addr add " + address(i) + "/24 dev eth0");
      must("ip -n " + ns(i) + " link set eth0 up");
      must("ip -n " + ns(i) + " link set lo up");
      // A default route: the host sends its multicast there, as a LAN host does.
      must("ip -n " + ns(i) + " route add default dev eth0");
    }
    if (drop_multicast) {
      must("ip netns exec " + sw + " nft add table bridge phlan");
      must("ip netns exec " + sw +
           " nft add chain bridge phlan multicast_drop '{ type filter hook forward priority 0; policy accept; }'");
      must("ip netns exec " + sw + " nft add rule bridge phlan multicast_drop ip daddr 224.0.0.0/4 counter drop");
    }
    ready_ = !::testing::Test::HasFatalFailure();
  }
  ~LanNet() { teardown(); }
  LanNet(const LanNet&) = delete;
  LanNet& operator=(const LanNet&) = delete;
  [[nodiscard]] bool ready() const { return ready_; }
  // Multicast frames the bridge dropped (unicast runs).
  [[nodiscard]] static uint64_t multicast_dropped() {
    const Output o = run("ip netns exec " + kPrefix + "-sw nft list table bridge phlan");
    std::smatch m;
    if (std::regex_search(o.text, m, std::regex("packets ([0-9]+)"))) return std::stoull(m[1]);
    return 0;
  }

 private:
  static void teardown() {
    for (int i = 0; i <= kHosts; ++i) run("ip netns del " + ns(i) + " 2>/dev/null");
    run("ip netns del " + kPrefix + "-sw 2>/dev/null");
  }
  bool ready_ = false;
};

// `seconds` into the run, a number from a log line matching `re` (group 1).
std::optional<double> number_in(const std::string& text, const std::string& re) {
  std::smatch m;
  if (std::regex_search(text, m, std::regex(re))) return std::stod(m[1]);
  return std::nullopt;
}

// Every host's `pheromesh run` of small-test in cells (each in its
// namespace, the same control key), with `args`; host I's output in
// OUT/hostI.txt and its run in OUT/hostI. Host `from_file` (if any) names the
// hosts in OUT/hosts.txt instead (--hosts-file, no --hosts, --dds-peers or
// --host-index: it finds itself by its address).
std::vector<Background> start_cell_hosts(const std::string& out, const std::string& args, int from_file = -1) {
  const std::string key = run(kBin + "/pheromesh key").text.substr(0, 64);
  {
    std::ofstream f(out + "/hosts.txt");
    f << "# the test's hosts, in host-index order\n"
      << address(0) << "   # the ground station\n\n"
      << address(1) << "\n"
      << address(2) << "\n";
  }
  std::vector<Background> hosts;
  for (int i = 0; i < kHosts; ++i) {
    const std::string where = i == from_file ? " --hosts-file " + out + "/hosts.txt"
                                             : " --hosts 3 --host-index " + std::to_string(i) + " --dds-peers " +
                                                   address(0) + "," + address(1) + "," + address(2);
    hosts.push_back(start({"/bin/sh", "-c",
                           "ip netns exec " + ns(i) + " env PHEROMESH_CONTROL_KEY=" + key + " " + kBin +
                               "/pheromesh run " + kSrc + "/scenarios/small-test.textproto" + where + " " + args +
                               " --out " + out + "/host" + std::to_string(i) + " 2>&1"},
                          out + "/host" + std::to_string(i) + ".txt"));
  }
  return hosts;
}

// The three hosts' launchers, then a monitor in the fourth namespace once the
// swarm flies; checks the swarm's metrics, each host's share and the monitor.
// `standby`: every region has a standby on the next host, and host 0 kills
// place agent 0 (its primary) mid-flight. `secure`: every process and the
// monitor authenticate with their identities (DDS Security; one directory of
// `pheromesh security init`, read by every host).
// `monitor_file`: the monitor names the hosts by a hosts file (--hosts-file).
void run_split_swarm(const std::string& tag, int domain, const std::string& profile_args, bool standby = false,
                     bool secure = false, bool monitor_file = false) {
  if (geteuid() != 0) GTEST_SKIP() << "network namespaces need root";
  // Without a profile flag the swarm flies in cells, the default.
  const bool cells = profile_args.find("--dds-profile") == std::string::npos;
  LanNet net(cells || profile_args.find("lan-unicast") != std::string::npos);
  ASSERT_TRUE(net.ready());
  const std::string out = out_dir(tag);
  const std::string key = run(kBin + "/pheromesh key").text.substr(0, 64);
  ASSERT_EQ(key.size(), 64U);
  std::string secure_args;
  if (secure) {
    const std::string dir = out + "/sec";
    const Output init = run(kBin + "/pheromesh security init " + dir + " --scenario " + kSrc +
                            "/scenarios/small-test.textproto --uavs 6");
    ASSERT_EQ(init.exit_code, 0) << init.text;
    secure_args = " --secure " + dir;
  }
  const std::string common = " --hosts " + std::to_string(kHosts) + " --domain " + std::to_string(domain) +
                             " --uavs 6 --ticks 375 --rate 25 --progress 0.5 " + profile_args +
                             (standby ? " --standby" : "") + secure_args;
  std::vector<Background> hosts;
  const auto t0 = Clock::now();
  for (int i = 0; i < kHosts; ++i) {
    const std::string cmd = "ip netns exec " + ns(i) + " env PHEROMESH_CONTROL_KEY=" + key + " " + kBin +
                            "/pheromesh run " + kSrc + "/scenarios/small-test.textproto --host-index " +
                            std::to_string(i) + " --out " + out + "/host" + std::to_string(i) + common +
                            (standby && i == 0 ? " --faults 'kill place:0 @5s'" : "") + " 2>&1";
    hosts.push_back(start({"/bin/sh", "-c", cmd}, out + "/host" + std::to_string(i) + ".txt"));
  }
  // The monitor joins once the ground station has started the swarm.
  const std::string ground_log = out + "/host0/logs/ground.log";
  const std::string ground_txt = out + "/host0.txt";
  const auto started = [&] { return slurp(ground_txt).find("sent to the swarm") != std::string::npos; };
  while (!started() && Clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(started()) << slurp(ground_txt);
  // Mid-flight: once the ground station's progress passed tick 50 (2 s of
  // the 15 s flight), so that a monitor that discovers slowly (Fast DDS over
  // unicast peers, on a host running other tests: it once heard no place
  // agent for 5 s) still sees the whole swarm fly.
  ASSERT_TRUE(wait_for_tick(ground_txt, 50, std::chrono::seconds(60)))
      << "the swarm's progress did not reach tick 50 within 60 s of its start:\n"
      << slurp(ground_txt);
  std::string peers;
  if (monitor_file) {
    std::ofstream(out + "/monitor-hosts.txt") << address(0) << "\n" << address(1) << "\n" << address(2) << "\n";
    peers = " --hosts-file " + out + "/monitor-hosts.txt";
  } else if (profile_args.find("--dds-peers") != std::string::npos) {
    peers = " --dds-peers " + address(0) + "," + address(1) + "," + address(2);
  }
  const std::string profile = cells                                                   ? "cells"
                              : profile_args.find("lan-unicast") != std::string::npos ? "lan-unicast"
                                                                                      : "lan";
  // In cells the monitor names the hosts only, as the operator does.
  const Background monitor = start({"/bin/sh", "-c",
                                    "ip netns exec " + ns(kHosts) + " " + kBin + "/pheromesh attach --domain " +
                                        std::to_string(domain) + (cells ? std::string() : " --dds-profile " + profile) +
                                        peers + secure_args + " --out " + out + "/monitor --timeout 30 2>&1"},
                                   out + "/monitor.txt");
  std::vector<int> codes;
  for (const auto& h : hosts) codes.push_back(wait_exit(h.pid, std::chrono::seconds(180)));
  const int monitor_code = wait_exit(monitor.pid, std::chrono::seconds(60));
  for (int i = 0; i < kHosts; ++i) {
    EXPECT_EQ(codes[static_cast<std::size_t>(i)], 0) << "host " << i << ":\n"
                                                     << slurp(out + "/host" + std::to_string(i) + ".txt");
  }

  // The swarm: every UAV of every host flew, every deposit is accounted for.
  const json m = read_metrics(out + "/host0");
  ASSERT_FALSE(m.is_null()) << slurp(ground_txt);
  EXPECT_EQ(m["uavs"], 6);
  EXPECT_EQ(m["place_agents_finished"], 4) << m.dump(2);
  EXPECT_EQ(m["hosts"], kHosts);
  expect_accounting(m);
  EXPECT_EQ(m["deposits_lost"], 0);
  EXPECT_GT(m["coverage"].get<double>(), 0.3);
  EXPECT_EQ(m["processes_crashed"], 0);
  // Each UAV flies on the host of its home place agent (UAV U: place agent
  // U % 4). Host 0 ran the ground station, place agents 0 and 3, UAVs 0, 3
  // and 4 (and the standby of region 2); host 1 place agent 1, UAVs 1 and 5
  // (standbys of regions 0 and 3); host 2 place agent 2, UAV 2 (standby of 1).
  const std::vector<std::size_t> share =
      standby ? std::vector<std::size_t>{7, 5, 3} : std::vector<std::size_t>{6, 3, 2};
  EXPECT_EQ(m["processes"].size(), share[0]) << m["processes"].dump(2);
  if (standby) {
    EXPECT_EQ(m["processes_killed"], 1);
    EXPECT_NE(slurp(ground_txt).find("region 0 is served by standby 1"), std::string::npos) << slurp(ground_txt);
  }
  for (int i = 1; i < kHosts; ++i) {
    std::ifstream in(out + "/host" + std::to_string(i) + "/host-" + std::to_string(i) + ".json");
    json h;
    ASSERT_TRUE(static_cast<bool>(in)) << "host " << i << " wrote no host-" << i << ".json";
    in >> h;
    EXPECT_EQ(h["host_index"], i);
    EXPECT_EQ(h["processes_crashed"], 0) << h.dump(2);
    EXPECT_EQ(h["processes"].size(), share[static_cast<std::size_t>(i)]) << h["processes"].dump(2);
  }
  const std::string ground = slurp(ground_txt);
  if (cells) EXPECT_NE(ground.find("profile cells"), std::string::npos) << ground;
  if (secure) {
    EXPECT_NE(ground.find("profile cells, DDS Security: identities in " + out + "/sec"), std::string::npos) << ground;
    EXPECT_NE(slurp(out + "/monitor.txt").find("DDS Security as 'monitor'"), std::string::npos);
  }
  const auto discovery = number_in(ground, "discovery complete: .* heard ([0-9.]+) s after the launch");
  ASSERT_TRUE(discovery.has_value()) << ground;
  ::testing::Test::RecordProperty("discovery_s", std::to_string(*discovery));
  std::printf("[lan] %s: discovery of 3 hosts %.2f s, wall %.1f s\n", tag.c_str(), *discovery,
              std::chrono::duration<double>(Clock::now() - t0).count());

  // The monitor found the swarm by its domain alone, showed all of it, and
  // saw the run end.
  const std::string mon = slurp(out + "/monitor.txt");
  EXPECT_EQ(monitor_code, 0) << mon;
  EXPECT_NE(mon.find("found run 'small-test'"), std::string::npos) << mon;
  const auto shown = number_in(mon, "attached: the whole swarm is shown .* ([0-9.]+) s after the monitor started");
  ASSERT_TRUE(shown.has_value()) << mon;
  EXPECT_NE(mon.find("every place agent finished: the run is over"), std::string::npos) << mon;
  const json mm = read_metrics(out + "/monitor");
  ASSERT_FALSE(mm.is_null()) << mon;
  EXPECT_EQ(mm["deposits_sent"], m["deposits_sent"]) << "the monitor's accounting is the processes' totals";
  EXPECT_EQ(mm["deposits_applied"], m["deposits_applied"]);
  std::printf("[lan] %s: the late monitor showed the whole swarm %.2f s after it started\n", tag.c_str(), *shown);
  if (profile != "lan") {
    std::printf("[lan] %s: multicast frames dropped on the bridge: %llu\n", tag.c_str(),
                static_cast<unsigned long long>(LanNet::multicast_dropped()));
  }
}

}  // namespace

TEST(Lan, ASwarmOverThreeHostsWithMulticastDiscoveryCompletesAndALateMonitorAttaches) {
  run_split_swarm("lan-multicast", 70, "--dds-profile lan");
}

TEST(Lan, ASwarmOverThreeHostsWithUnicastPeersCompletesWithoutMulticastAndALateMonitorAttaches) {
  run_split_swarm("lan-unicast", 71,
                  "--dds-profile lan-unicast --dds-peers " + address(0) + "," + address(1) + "," + address(2));
}

// Secure (DDS Security) on one vendor; a mixed swarm cannot be secure
// (docs/security.md), and flies open. The monitor names the hosts by a hosts file.
TEST(LanCells, ASwarmOverThreeHostsInCellsByDefaultCompletesWithoutMulticastAndAMonitorNamingTheHostsAttaches) {
  const char* backend = std::getenv("PHEROMESH_DDS");
  run_split_swarm("lan-cells", 75, "--dds-peers " + address(0) + "," + address(1) + "," + address(2),
                  /*standby=*/false, /*secure=*/backend == nullptr || std::string(backend) != "mixed",
                  /*monitor_file=*/true);
}

// Lockstep over three hosts in cells: the ground station on host 0 conducts
// every host's processes, and the swarm's numbers are the simulator's. Host
// 2 names the hosts with a hosts file and finds its own index there.
TEST(LanCells, ALockstepSwarmOverThreeHostsInCellsGivesTheSimulatorsNumbers) {
  if (geteuid() != 0) GTEST_SKIP() << "network namespaces need root";
  LanNet net(/*drop_multicast=*/true);
  ASSERT_TRUE(net.ready());
  const std::string out = out_dir("lan-cells-lockstep");
  const std::string args = "--uavs 6 --ticks 150 --seed 4";
  const std::vector<Background> hosts =
      start_cell_hosts(out, "--domain 76 --clock lockstep --tracks " + args, /*from_file=*/2);
  for (int i = 0; i < kHosts; ++i) {
    EXPECT_EQ(wait_exit(hosts[static_cast<std::size_t>(i)].pid, std::chrono::seconds(180)), 0)
        << "host " << i << ":\n"
        << slurp(out + "/host" + std::to_string(i) + ".txt");
  }
  expect_same_as_sim(out + "/host0", "small-test.textproto", args, "lan-cells-lockstep");
  const std::string host2 = slurp(out + "/host2.txt");
  EXPECT_NE(host2.find("--hosts-file " + out + "/hosts.txt: 3 hosts, this is host 2 (line 5, " + address(2) + ")"),
            std::string::npos)
      << host2;
}

// What a swarm over several hosts cannot do is refused before anything
// starts, and the message says what to do instead.
TEST(Cli, SeveralHostsRefuseWhatCannotWorkAndSayWhatToDo) {
  const std::string base =
      kBin + "/pheromesh run " + kSrc + "/scenarios/small-test.textproto --out " + out_dir("lan-cli") + " --domain 72 ";
  const std::string key = "PHEROMESH_CONTROL_KEY=" + std::string(64, 'a') + " ";
  struct Case {
    std::string env, args, says;
  };
  const std::vector<Case> cases{
      {key, "--hosts 3 --host-index 3 --dds-profile lan", "--host-index 3 is not below --hosts 3"},
      {key, "--hosts 3 --ground-host 5 --dds-profile lan", "--ground-host 5"},
      {key, "--hosts 2", "needs --dds-peers with every host's address in host-index order"},
      {key, "--hosts 2 --dds-peers 127.0.0.1,192.0.2.7 --host-index 1", "no interface of this host has that address"},
      {key, "--hosts 2 --dds-profile onehost", "keeps traffic on this host"},
      {key, "--hosts 2 --dds-profile lan-unicast", "needs --dds-peers"},
      {"env -u PHEROMESH_CONTROL_KEY ", "--hosts 2 --dds-profile lan", "pheromesh key"},
      {key, "--hosts 2 --host-index 1 --dds-profile lan --http 0", "runs on host 0"},
      {key, "--hosts 2 --host-index 1 --dds-profile lan --faults 'kill uav:0 @2s'", "uav-0 does not run on host 1"},
      {key, "--hosts 2 --dds-profile lan --faults 'loss 10% @1s for 1s'", "do not work with --hosts"},
  };
  for (const auto& c : cases) {
    const Output o = run("env " + c.env + base + c.args);
    EXPECT_EQ(o.exit_code, 2) << c.args << "\n" << o.text;
    EXPECT_NE(o.text.find(c.says), std::string::npos) << c.args << "\n" << o.text;
  }
  // --hosts-file: what the file cannot be, named by file and line, and the
  // flags it stands for given beside it (docs/deployment.md).
  const std::string files = out_dir("lan-cli-hosts");
  const auto hosts_file = [&](const std::string& name, const std::string& text) {
    std::ofstream(files + "/" + name) << text;
    return files + "/" + name;
  };
  const std::string two = hosts_file("two.txt", "127.0.0.1\n192.0.2.7\n");
  const std::vector<Case> file_cases{
      {key, "--hosts-file " + hosts_file("empty.txt", "# no host yet\n\n"), "empty.txt: no host in it"},
      {key, "--hosts-file " + hosts_file("words.txt", "127.0.0.1\n192.0.2.7 192.0.2.8\n"),
       "words.txt:2: '192.0.2.7 192.0.2.8': one host per line"},
      {key, "--hosts-file " + hosts_file("twice.txt", "127.0.0.1\n192.0.2.7\n127.0.0.1 # again\n"),
       "twice.txt:3: '127.0.0.1' is 127.0.0.1, as line 1"},
      {key, "--hosts-file " + hosts_file("unknown.txt", "127.0.0.1\nno-such-host.invalid\n"),
       "unknown.txt:2: 'no-such-host.invalid': does not resolve"},
      {key, "--hosts-file " + two + " --hosts 2", "gives --hosts (2 hosts): leave --hosts 2 out"},
      {key, "--hosts-file " + two + " --host-index 0 --dds-peers 127.0.0.1,192.0.2.7",
       "gives --dds-peers (every host's address, in its order): leave --dds-peers"},
      {key + "PHEROMESH_DDS_PEERS=127.0.0.1 ", "--hosts-file " + two, "leave $PHEROMESH_DDS_PEERS (127.0.0.1) out"},
      {key, "--hosts-file " + two + " --host-index 2", "--host-index 2 is not below the 2 hosts of --hosts-file"},
      {key, "--hosts-file " + hosts_file("elsewhere.txt", "192.0.2.7\n192.0.2.8\n"),
       "no entry is an address of this host; give --host-index"},
      {key, "--hosts-file " + hosts_file("loopbacks.txt", "127.0.0.1\n127.0.0.2\n"),
       "several entries are addresses of this host (host 0 (line 1, 127.0.0.1), host 1 (line 2, 127.0.0.2))"},
      // The file's list, checked as --dds-peers' is: entry 1 is not this host's.
      {key, "--hosts-file " + two + " --host-index 1", "no interface of this host has that address"},
  };
  for (const auto& c : file_cases) {
    const Output o = run("env " + c.env + base + c.args);
    EXPECT_EQ(o.exit_code, 2) << c.args << "\n" << o.text;
    EXPECT_NE(o.text.find(c.says), std::string::npos) << c.args << "\n" << o.text;
  }
  const Output missing = run("env " + key + base + "--hosts-file " + files + "/none.txt");
  EXPECT_EQ(missing.exit_code, 105) << missing.text;  // a flag's value fails its check (docs/exit-codes.md)
  const Output attach = run(kBin + "/pheromesh attach --domain 72 --timeout 1 --out " + files +
                            "/attach --hosts-file " + two + " --dds-peers 127.0.0.1");
  EXPECT_EQ(attach.exit_code, 2) << attach.text;
  EXPECT_NE(attach.text.find("gives --dds-peers (every host's address): leave --dds-peers (127.0.0.1) out"),
            std::string::npos)
      << attach.text;
  // A key for every host.
  const Output k = run(kBin + "/pheromesh key");
  EXPECT_EQ(k.exit_code, 0);
  EXPECT_TRUE(std::regex_match(k.text, std::regex("[0-9a-f]{64}\n"))) << k.text;
}

TEST(Cli, AMonitorWithNoSwarmOnItsDomainSaysSoAndAGroundStationNeedsAScenarioOrAttach) {
  const Output a = run(kBin + "/pheromesh attach --domain 73 --timeout 1 --out " + out_dir("attach-none"));
  EXPECT_EQ(a.exit_code, 2) << a.text;
  EXPECT_NE(a.text.find("no place agent published a run on domain 73"), std::string::npos) << a.text;
  const Output g = run(kBin + "/pheromesh-ground --domain 73");
  EXPECT_NE(g.exit_code, 0);
  EXPECT_NE(g.text.find("--scenario is required (or --attach"), std::string::npos) << g.text;
}

TEST(Lan, AStandbyOnAnotherHostServesARegionWhoseHostKilledItsPrimaryInCells) {
  run_split_swarm("lan-standby", 74, "--dds-peers " + address(0) + "," + address(1) + "," + address(2), true);
}

// One host's link cut mid-run, in cells: the bridge drops host 2's frames
// for 100 ticks of the run (4 s), then carries them again. The ground station (host 0) sees region 2 go
// dark and come back; UAV 2, which flies on host 2 beside its home place
// agent (placement by locality), keeps its gateway through the cut and flies
// every tick; the run ends by itself with every deposit accounted for.
TEST(Lan, AHostWhoseLinkIsCutMidRunDarkensItsRegionAndItsUavFliesOnBesideItsHome) {
  if (geteuid() != 0) GTEST_SKIP() << "network namespaces need root";
  LanNet net(/*drop_multicast=*/true);
  ASSERT_TRUE(net.ready());
  const std::string out = out_dir("lan-cut");
  const auto t0 = Clock::now();
  const std::vector<Background> hosts =
      start_cell_hosts(out, "--domain 77 --uavs 6 --ticks 375 --rate 25 --progress 0.5");
  const std::string ground_txt = out + "/host0.txt";
  const auto started = [&] { return slurp(ground_txt).find("sent to the swarm") != std::string::npos; };
  while (!started() && Clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_TRUE(started()) << slurp(ground_txt);
  // Well into the flight (tick 75 of 375, every region heard): the cut
  // falls mid-run, with time left for region 2 to come back before the end.
  ASSERT_TRUE(wait_for_tick(ground_txt, 75, std::chrono::seconds(60)))
      << "the swarm's progress did not reach tick 75 within 60 s of its start:\n"
      << slurp(ground_txt);
  // The cut: the switch drops every frame from and to host 2 (its cable is
  // cut; the host does not notice, as a host behind a broken switch port
  // does not).
  const std::string sw = "ip netns exec " + kPrefix + "-sw nft ";
  must(sw + "add table bridge phcut");
  must(sw + "add chain bridge phcut cut '{ type filter hook forward priority 0; policy accept; }'");
  must(sw + "add rule bridge phcut cut ip saddr " + address(2) + " drop");
  must(sw + "add rule bridge phcut cut ip daddr " + address(2) + " drop");
  // It lasts 100 ticks of the run (4 s at 25 Hz: the outage is what the test
  // is about) and at least until the ground station reports region 2 dark;
  // then the link carries frames again.
  const uint32_t cut_tick = progress_tick(ground_txt);
  const bool dark = wait_for_text(ground_txt, "place agent 2 lost (liveliness)", std::chrono::seconds(15));
  const bool long_enough = wait_for_tick(ground_txt, cut_tick + 100, std::chrono::seconds(30));
  must(sw + "delete table bridge phcut");
  ASSERT_TRUE(dark) << "the ground station did not report place agent 2 lost within 15 s of the cut:\n"
                    << slurp(ground_txt);
  ASSERT_TRUE(long_enough) << "the run's progress did not pass tick " << cut_tick + 100 << " within 30 s of the cut:\n"
                           << slurp(ground_txt);
  std::vector<int> codes;
  for (const auto& h : hosts) codes.push_back(wait_exit(h.pid, std::chrono::seconds(180)));
  for (int i = 0; i < kHosts; ++i) {
    EXPECT_EQ(codes[static_cast<std::size_t>(i)], 0) << "host " << i << ":\n"
                                                     << slurp(out + "/host" + std::to_string(i) + ".txt");
  }
  const std::string ground = slurp(ground_txt);
  // The ground station saw region 2 go dark, and come back.
  EXPECT_NE(ground.find("place agent 2 lost (liveliness); region 2 has no live place agent"), std::string::npos)
      << ground;
  EXPECT_NE(ground.find("place agent 2 is back at tick"), std::string::npos) << ground;
  // No other place agent went dark: the cut was host 2's alone.
  for (int r : {0, 1, 3}) {
    EXPECT_EQ(ground.find("place agent " + std::to_string(r) + " lost"), std::string::npos) << ground;
  }
  // UAV 2 (home 2, on host 2) flew every tick and kept its gateway.
  const std::string uav2 = slurp(out + "/host2/logs/uav-2.log");
  EXPECT_NE(uav2.find("uav 2 finished at tick 375"), std::string::npos) << uav2;
  EXPECT_EQ(uav2.find("naming place agent"), std::string::npos) << uav2;  // no backup needed
  const json m = read_metrics(out + "/host0");
  ASSERT_FALSE(m.is_null()) << ground;
  EXPECT_EQ(m["uavs"], 6);
  EXPECT_EQ(m["place_agents_finished"], 4) << m.dump(2);
  expect_accounting(m);
  EXPECT_EQ(m["processes_crashed"], 0);
  std::printf("[lan] lan-cut: deposits sent %lld, applied %lld, lost %lld\n", m["deposits_sent"].get<long long>(),
              m["deposits_applied"].get<long long>(), m["deposits_lost"].get<long long>());
}
