// The ground station's /metrics text (console/swarm_metrics.hpp) and its line
// to the launcher (console/launcher_link.hpp, over a real socket pair).
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <thread>

#include "pheromesh/console/launcher_link.hpp"
#include "pheromesh/console/swarm_metrics.hpp"

namespace pheromesh::console {
namespace {

bool has_line(const std::string& text, const std::string& line) { return text.find("\n" + line + "\n") != std::string::npos; }

TEST(SwarmMetrics, CountsUavsAndPlaceAgentsByLivenessAndShowsOptionalFamiliesOnlyWhenPresent) {
  ConsoleState st;
  st.tick = 42;
  st.uavs[0].liveness = Liveness::Alive;
  st.uavs[1].liveness = Liveness::Dead;
  st.uavs[2].liveness = Liveness::Alive;
  RegionView r0;
  r0.id = 0;
  r0.liveness = Liveness::Alive;
  r0.deposits_applied = 17;
  RegionView r1;
  r1.id = 1;
  r1.liveness = Liveness::Stale;
  st.regions = {r0, r1};
  SwarmCounters c;
  c.coverage = 0.25;
  c.targets_found = 1;
  c.targets_total = 3;
  c.commands_refused = 2;
  const std::string t = swarm_metrics_text(st, c);
  EXPECT_TRUE(has_line(t, "pheromesh_uavs{state=\"alive\"} 2")) << t;
  EXPECT_TRUE(has_line(t, "pheromesh_uavs{state=\"dead\"} 1"));
  EXPECT_TRUE(has_line(t, "pheromesh_uavs{state=\"stale\"} 0"));
  EXPECT_TRUE(has_line(t, "pheromesh_place_agents{state=\"stale\"} 1"));
  EXPECT_TRUE(has_line(t, "pheromesh_tick 42"));
  EXPECT_TRUE(has_line(t, "pheromesh_coverage_ratio 0.25"));
  EXPECT_TRUE(has_line(t, "pheromesh_targets{status=\"total\"} 3"));
  EXPECT_TRUE(has_line(t, "pheromesh_region_deposits_applied_total{region=\"0\"} 17"));
  EXPECT_TRUE(has_line(t, "pheromesh_region_up{region=\"0\"} 1"));
  EXPECT_TRUE(has_line(t, "pheromesh_region_up{region=\"1\"} 0"));
  EXPECT_TRUE(has_line(t, "pheromesh_console_commands_total{result=\"refused\"} 2"));
  EXPECT_EQ(t.find("pheromesh_console_http_requests_total"), std::string::npos) << "no server, no family";
  EXPECT_EQ(t.find("pheromesh_recording_bytes_total"), std::string::npos);
  c.http_requests = 5;
  c.recording_bytes = 1000;
  const std::string u = swarm_metrics_text(st, c);
  EXPECT_TRUE(has_line(u, "pheromesh_console_http_requests_total 5"));
  EXPECT_TRUE(has_line(u, "pheromesh_recording_bytes_total 1000"));
  // Samples refused as implausible, by who and why (core/plausibility.hpp).
  EXPECT_EQ(u.find("pheromesh_samples_refused_total"), std::string::npos) << "none counted, no family";
  c.samples_refused["places"]["unknown_uav"] = 3;
  c.samples_refused["uavs"]["foreign_clock"] = 0;
  const std::string v = swarm_metrics_text(st, c);
  EXPECT_TRUE(has_line(v, "pheromesh_samples_refused_total{by=\"places\",reason=\"unknown_uav\"} 3")) << v;
  EXPECT_TRUE(has_line(v, "pheromesh_samples_refused_total{by=\"uavs\",reason=\"foreign_clock\"} 0")) << v;
}

struct Pair {
  int fds[2] = {-1, -1};
  Pair() { EXPECT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, fds), 0); }
  ~Pair() {
    for (int fd : fds) {
      if (fd >= 0) ::close(fd);
    }
  }
};

// The launcher's side: reads one request line, answers `reply` (if any).
std::thread launcher(int fd, std::string reply, std::string& got) {
  return std::thread([fd, reply = std::move(reply), &got] {
    char buf[256];
    std::string line;
    while (line.empty() || line.back() != '\n') {
      const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
      if (n <= 0) return;
      line.append(buf, static_cast<std::size_t>(n));
    }
    got = line;
    if (!reply.empty()) ::send(fd, reply.data(), reply.size(), MSG_NOSIGNAL);
  });
}

TEST(LauncherLink, SendsOneLineAndMapsTheAnswer) {
  {
    Pair p;
    std::string got;
    auto t = launcher(p.fds[1], "ok SIGKILL sent to uav-3 (pid 77)\n", got);
    const auto a = LauncherLink(p.fds[0]).ask("kill uav 3");
    t.join();
    EXPECT_EQ(got, "kill uav 3\n");
    EXPECT_EQ(a.status, 200);
    EXPECT_EQ(a.message, "SIGKILL sent to uav-3 (pid 77)");
  }
  {
    Pair p;
    std::string got;
    auto t = launcher(p.fds[1], "error uav-3 is running; kill it first\n", got);
    const auto a = LauncherLink(p.fds[0]).ask("restart uav 3");
    t.join();
    EXPECT_EQ(a.status, 409);
    EXPECT_EQ(a.message, "uav-3 is running; kill it first");
  }
}

TEST(LauncherLink, NoLauncherASilentOneAndAClosedOneAreRefused) {
  EXPECT_FALSE(LauncherLink(-1).connected());
  EXPECT_EQ(LauncherLink(-1).ask("kill uav 0").status, 409);
  {
    Pair p;
    std::string got;
    auto t = launcher(p.fds[1], "", got);  // reads, never answers
    const auto a = LauncherLink(p.fds[0], std::chrono::milliseconds(200)).ask("kill place 1");
    t.join();
    EXPECT_EQ(a.status, 504);
  }
  {
    Pair p;
    ::close(p.fds[1]);
    p.fds[1] = -1;
    EXPECT_EQ(LauncherLink(p.fds[0]).ask("kill uav 0").status, 409);
  }
}

}  // namespace
}  // namespace pheromesh::console
