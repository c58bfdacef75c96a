// The swarm in a MAVLink ground-control station (docs/mavlink.md), checked
// by a MAVLink library nobody here wrote: web/e2e/mavlink_gcs.mjs decodes
// the stream of a real `pheromesh run --mavlink` with node-mavlink and
// mavlink-mappings (installed with the web console's npm tools), and sends
// an unsigned and a signed pause, a signed continue, then a signed disarm
// that stops the run; and the stream of `pheromesh replay --mavlink` of a
// recording, whose playback the station pauses and continues. Domain 98.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <csignal>

#include <cmath>
#include <numbers>
#include <sstream>

#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers

namespace {

// A UDP port nobody holds now (the kernel's choice, released at once).
int free_udp_port() {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  close(fd);
  return ntohs(a.sin_port);
}

struct Track {
  uint32_t tick;
  uint32_t uav;
  double x, y;  // [cell]
};

std::vector<Track> read_tracks(const std::string& path) {
  std::vector<Track> out;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header: tick,uav,x,y,role
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string tick, uav, x, y;
    if (std::getline(s, tick, ',') && std::getline(s, uav, ',') && std::getline(s, x, ',') && std::getline(s, y, ',')) {
      out.push_back({static_cast<uint32_t>(std::stoul(tick)), static_cast<uint32_t>(std::stoul(uav)), std::stod(x),
                     std::stod(y)});
    }
  }
  return out;
}

// The test's own inverse of the geo frame (docs/scenario-format.md "geo"),
// written apart from core::geo_to_map: WGS84 radii at the origin's latitude.
struct Frame {
  double lat0, lon0, cell_m;
  [[nodiscard]] std::pair<double, double> cell_of(double lat_e7, double lon_e7) const {
    constexpr double a = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f), rad = std::numbers::pi / 180;
    const double s = std::sin(lat0 * rad);
    const double w = 1 - e2 * s * s;
    const double m = a * (1 - e2) / (w * std::sqrt(w)), n = a / std::sqrt(w);
    const double north = (lat_e7 / 1e7 - lat0) * rad * m;
    const double east = (lon_e7 / 1e7 - lon0) * rad * n * std::cos(lat0 * rad);
    return {east / cell_m, -north / cell_m};
  }
};

// Checks that every decoded position lies within one cell of a position the
// run recorded for that UAV, at the flight height; returns how many it checked.
std::size_t positions_near_tracks(const json& positions, const std::vector<Track>& tracks, const Frame& geo) {
  std::size_t checked = 0;
  for (const auto& p : positions) {
    const uint32_t uav = p["sysid"].get<uint32_t>() - 1;
    const auto [x, y] = geo.cell_of(p["lat"].get<double>(), p["lon"].get<double>());
    double nearest = 1e9;
    for (const Track& t : tracks) {
      if (t.uav == uav) nearest = std::min(nearest, std::hypot(t.x - x, t.y - y));
    }
    EXPECT_LE(nearest, 1.0) << "uav " << uav << " at (" << x << ", " << y << ")";
    EXPECT_EQ(p["alt"], 430000);  // 400 m ground + 30 m flight height [mm]
    ++checked;
  }
  return checked;
}

}  // namespace

TEST(Mavlink, NodeMavlinkDecodesTheSwarmAndOnlyASignedPauseStopsIt) {
  const std::string e2e = PHEROMESH_WEB_E2E_DIR;
  const std::string script = e2e + "/mavlink_gcs.mjs";
  if (!fs::exists(script) || !fs::exists(e2e + "/../node_modules/node-mavlink/package.json")) {
    GTEST_SKIP() << "no " << script << " beside node_modules/node-mavlink: build the web console (npm)";
  }
  const std::string out = out_dir("mavlink");
  const std::string report = out + "-gcs.json";
  const int port = free_udp_port();
  const Frame geo{47.4, 8.5, 2.0};
  Background gcs = start({"/usr/bin/env", "node", script, "--port", std::to_string(port), "--uavs", "4", "--key-file",
                          out + "/mavlink.key", "--report", report, "--timeout", "60", "--stop", "1"},
                         out + "-gcs.txt");
  // 750 ticks at 50 Hz: 15 s of flight and the pause on top, were it not
  // stopped from the station after about 8 s.
  Background run = start_run("small-test.textproto", out, 98,
                             "--tracks --mavlink udp:127.0.0.1:" + std::to_string(port) +
                                 " --mavlink-rate-hz 10 --set run.ticks=750 --set geo.origin_lat_deg=47.4 --set "
                                 "geo.origin_lon_deg=8.5 --set geo.origin_alt_m=400 --set geo.cell_size_m=2");
  const int gcs_rc = wait_exit(gcs.pid, std::chrono::seconds(75));
  gcs.pid = -1;
  EXPECT_EQ(gcs_rc, 0) << slurp(out + "-gcs.txt");
  const int run_rc = wait_exit(run.pid, std::chrono::seconds(90));
  run.pid = -1;
  // The station's stop is the operator's interrupt: the swarm stopped in
  // order, the outputs written, exit 130 (docs/exit-codes.md).
  ASSERT_EQ(run_rc, 130) << slurp(out + ".txt");
  EXPECT_NE(slurp(out + ".txt").find("a MAVLink station's disarm"), std::string::npos) << slurp(out + ".txt");
  ASSERT_FALSE(read_metrics(out).empty()) << "no metrics.json";

  const json r = json::parse(slurp(report));
  EXPECT_EQ(r["crc_errors"], 0);
  EXPECT_EQ(r["invalid_packets"], 0);
  EXPECT_GT(r["valid_packets"].get<int>(), 100);
  for (const char* m : {"HEARTBEAT", "GLOBAL_POSITION_INT", "ATTITUDE", "ADSB_VEHICLE", "SYS_STATUS"}) {
    EXPECT_GT(r["by_message"].value(m, 0), 0) << m;
  }
  EXPECT_EQ(r["heartbeat_systems"], json({1, 2, 3, 4}));

  // Every position decoded lies within one cell of a position the ground
  // station recorded for that UAV (OUT/tracks.csv, docs/outputs.md).
  const auto tracks = read_tracks(out + "/tracks.csv");
  ASSERT_FALSE(tracks.empty());
  // The stop came long before tick 750.
  uint32_t last_tick = 0;
  for (const Track& t : tracks) last_tick = std::max(last_tick, t.tick);
  EXPECT_LT(last_tick, 700U);
  EXPECT_GT(positions_near_tracks(r["positions"], tracks, geo), 40U);

  // The ground station counted the unsigned pause and took the two signed commands.
  const json m = json::parse(slurp(out + "/mavlink.json"));
  EXPECT_GE(m["commands"]["unsigned_refused"].get<int>(), 1) << m.dump();
  EXPECT_EQ(m["commands"]["accepted"], 3) << m.dump();
  EXPECT_EQ(m["commands"]["bad_signature"], 0) << m.dump();
}

// `pheromesh replay --mavlink` of a recording (the simulator's, 30 s of
// simulated time, 4 UAVs): node-mavlink decodes the stream, whose positions
// are the run's (tracks.csv), and steers the playback with unsigned
// commands: pause and continue ACCEPTED, disarm UNSUPPORTED. No DDS.
TEST(Mavlink, AReplayStreamsTheRecordedRunAndTakesPauseAndContinueForItsPlayback) {
  const std::string e2e = PHEROMESH_WEB_E2E_DIR;
  const std::string script = e2e + "/mavlink_gcs.mjs";
  if (!fs::exists(script) || !fs::exists(e2e + "/../node_modules/node-mavlink/package.json")) {
    GTEST_SKIP() << "no " << script << " beside node_modules/node-mavlink: build the web console (npm)";
  }
  const std::string out = out_dir("mavlink-replay");
  const Output sim = run(kBin + "/pheromesh sim " + kSrc + "/scenarios/small-test.textproto --ticks 1500 --quiet " +
                         "--tracks --record " + out + "/run.phrec --out " + out +
                         " --set geo.origin_lat_deg=47.4 --set geo.origin_lon_deg=8.5 --set geo.origin_alt_m=400 " +
                         "--set geo.cell_size_m=2");
  ASSERT_EQ(sim.exit_code, 0) << sim.text;
  const std::string report = out + "-gcs.json";
  const int port = free_udp_port();
  Background gcs = start({"/usr/bin/env", "node", script, "--port", std::to_string(port), "--uavs", "4", "--replay",
                          "1", "--report", report, "--timeout", "60"},
                         out + "-gcs.txt");
  // exec: the SIGINT below reaches the replay itself; its log (stderr) beside its stdout.
  Background replay =
      start({"/bin/sh", "-c",
             "exec " + kBin + "/pheromesh replay " + out +
                 "/run.phrec --http 0 --mavlink udp:127.0.0.1:" + std::to_string(port) + " --mavlink-rate-hz 10 2>&1"},
            out + "-replay.txt");
  const int gcs_rc = wait_exit(gcs.pid, std::chrono::seconds(75));
  gcs.pid = -1;
  EXPECT_EQ(gcs_rc, 0) << slurp(out + "-gcs.txt") << slurp(out + "-replay.txt");
  // The replay runs until it is stopped, as without --mavlink.
  ::kill(replay.pid, SIGINT);
  EXPECT_EQ(wait_exit(replay.pid, std::chrono::seconds(20)), 0);
  replay.pid = -1;
  const std::string log = slurp(out + "-replay.txt");
  EXPECT_NE(log.find("MAVLink to udp:127.0.0.1:" + std::to_string(port)), std::string::npos) << log;
  EXPECT_NE(log.find("paused the playback at"), std::string::npos) << log;
  EXPECT_NE(log.find("MAVLink command 400 (param1 0) is unsupported"), std::string::npos) << log;

  const json r = json::parse(slurp(report));
  EXPECT_EQ(r["crc_errors"], 0);
  EXPECT_EQ(r["invalid_packets"], 0);
  for (const char* m : {"HEARTBEAT", "GLOBAL_POSITION_INT", "ATTITUDE", "ADSB_VEHICLE", "SYS_STATUS"}) {
    EXPECT_GT(r["by_message"].value(m, 0), 0) << m;
  }
  EXPECT_EQ(r["heartbeat_systems"], json({1, 2, 3, 4}));
  // Every position lies within one cell of one the run recorded for that UAV.
  const Frame geo{47.4, 8.5, 2.0};
  const auto tracks = read_tracks(out + "/tracks.csv");
  ASSERT_FALSE(tracks.empty());
  EXPECT_GT(positions_near_tracks(r["positions"], tracks, geo), 40U);
}

// A --mavlink that is not udp:HOST:PORT, or a rate out of range, is refused
// by every program that takes it, naming the flag, before anything starts
// (no DDS: these never get that far).
TEST(Mavlink, ABadTargetOrRateIsRefusedNamingTheFlagBeforeAnythingStarts) {
  const std::string scenario = kSrc + "/scenarios/small-test.textproto";
  // replay's FILE is only checked to exist before the flags are.
  for (const std::string& program :
       {kBin + "/pheromesh run " + scenario, kBin + "/pheromesh attach --domain 98",
        kBin + "/pheromesh-ground --scenario " + scenario, kBin + "/pheromesh replay " + scenario}) {
    const Output target = run(program + " --mavlink tcp:127.0.0.1:14550");
    EXPECT_EQ(target.exit_code, 105) << program;  // a flag's value fails its check (docs/exit-codes.md)
    EXPECT_NE(target.text.find("--mavlink"), std::string::npos) << target.text;
    EXPECT_NE(target.text.find("give udp:HOST:PORT"), std::string::npos) << target.text;
    const Output rate = run(program + " --mavlink udp:127.0.0.1:14550 --mavlink-rate-hz 50");
    EXPECT_EQ(rate.exit_code, 105) << program;
    EXPECT_NE(rate.text.find("--mavlink-rate-hz"), std::string::npos) << rate.text;
    EXPECT_NE(rate.text.find("must be between 0.2 and 20 [Hz]"), std::string::npos) << rate.text;
  }
}
