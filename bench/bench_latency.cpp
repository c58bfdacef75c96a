// pheromesh-bench-latency: deposit -> tile-update latency and per-process RSS
// for each DDS backend, measured in one run, with Cyclone's ddsperf
// round trip on the same machine for scale.
//
// For each backend a real place agent (pheromesh-place, realtime clock at
// --rate Hz, one region) and a client process (this binary, `client`) run on
// loopback. The client deposits a path visit (Shao 2020 eq. (6), Shao 2020 eq. (7)) on a
// fresh cell and times until a tile sample shows that cell changed; between
// samples it waits a random 2-5 ms so deposits fall anywhere in the place
// agent's tick. The figure therefore includes up to one tick of waiting
// (1 ms at the default 1000 Hz) besides the two DDS hops.
//
// With --security the same is measured per vendor without DDS Security and
// with it at each governance protection (none: authenticated and
// access-controlled only; sign: GMAC; encrypt: AES-GCM), all in one run
// (docs/security.md).
//
//   pheromesh-bench-latency [--samples N] [--rate HZ] [--domain D] [--json FILE] [--security]
#include <fcntl.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <tuple>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/core/grid.hpp"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace pheromesh;  // NOLINT

namespace {

const std::string kScenario = std::string(PHEROMESH_BENCH_DIR) + "/latency.textproto";

long rss_kb(pid_t pid) {
  std::ifstream in("/proc/" + (pid == 0 ? std::string("self") : std::to_string(pid)) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(std::min<double>(static_cast<double>(v.size() - 1), p * static_cast<double>(v.size())));
  return v[i];
}

// ------------------------------------------------------------------ client
constexpr int32_t kMapSide = 32;   // bench/latency.textproto
constexpr int32_t kTileSide = 16;

int client(const std::string& vendor, uint32_t domain, int samples, const std::string& secure) {
  bus::BusOptions o;
  o.process_name = "bench-client";
  o.domain = domain;
  // A test identity that may deposit and read fields (security.hpp).
  o.secure_dir = secure;
  o.identity = "probe-0";
  auto made = bus::make_bus(vendor, o);
  if (!made) {
    std::fprintf(stderr, "%s\n", made.error().message.c_str());
    return 3;
  }
  auto& b = *made.value();
  // The place agent's field (what every place agent composes views from and
  // the ground station shows): one sample per place tick with every tile.
  b.subscribe_fields();
  // The latest values of every (layer, tile).
  std::map<std::tuple<int, int32_t, int32_t>, std::vector<float>> latest;
  std::vector<core::FieldMsg> fields;
  auto receive = [&] {
    fields.clear();
    b.take_fields(fields);
    for (auto& f : fields) {
      for (auto& t : f.tiles) latest[{t.layer, t.tile.tx, t.tile.ty}] = std::move(t.values);
    }
    return !fields.empty();
  };
  // The values of `cell` in every layer.
  auto values_at = [&](core::Cell c) {
    std::vector<float> v;
    for (const auto& [key, values] : latest) {
      const auto& [layer, tx, ty] = key;
      if (tx != c.x / kTileSide || ty != c.y / kTileSide) continue;
      v.push_back(values.at(static_cast<std::size_t>((c.y % kTileSide) * kTileSide + c.x % kTileSide)));
    }
    return v;
  };
  b.offer_deposits(std::vector<core::RegionId>{0});
  const auto deadline = Clock::now() + std::chrono::seconds(60);
  while ((b.matched_deposit_readers(0) == 0 || latest.size() < 4) && Clock::now() < deadline) {
    receive();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (latest.size() < 4) {
    std::fprintf(stderr, "no place agent answered within 60 s\n");
    return 1;
  }
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> gap_us(2000, 5000);
  std::vector<double> lat_us;
  uint32_t seq = 0;
  int lost = 0;
  const int warmup = 20;
  for (int n = 0; n < samples + warmup && n < kMapSide * kMapSide; ++n) {
    // Each deposit on a cell never visited before: the only change it can see.
    const core::Cell cell{n % kMapSide, n / kMapSide};
    std::this_thread::sleep_for(std::chrono::microseconds(gap_us(rng)));
    receive();
    const std::vector<float> before = values_at(cell);
    const auto t0 = Clock::now();
    b.publish_deposit({0, ++seq, 0, 0, static_cast<uint8_t>(core::DepositKind::PathVisit), 0, cell, 1.0F, {}}, 0);
    bool seen = false;
    while (!seen && Clock::now() - t0 < std::chrono::seconds(2)) {
      if (receive()) seen = values_at(cell) != before;
      if (!seen) std::this_thread::sleep_for(std::chrono::microseconds(20));
    }
    if (!seen) {
      ++lost;
      continue;
    }
    if (n >= warmup) lat_us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  double mean = 0;
  for (double v : lat_us) mean += v / static_cast<double>(lat_us.size());
  std::printf("latency_us p50 %.1f p99 %.1f mean %.1f n %zu lost %d rss_kb %ld\n", percentile(lat_us, 0.5),
              percentile(lat_us, 0.99), mean, lat_us.size(), lost, rss_kb(0));
  return 0;
}

// ------------------------------------------------------------------ driver
pid_t spawn(const std::vector<std::string>& args, const std::string& out_path, const std::vector<std::string>& env = {}) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, STDOUT_FILENO);
      dup2(fd, STDERR_FILENO);
    }
    for (const auto& e : env) putenv(const_cast<char*>(e.c_str()));  // NOLINT: the child's own copy
    std::vector<char*> argv;
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

int wait_for(pid_t pid, std::chrono::seconds timeout) {
  const auto deadline = Clock::now() + timeout;
  while (Clock::now() < deadline) {
    int st = 0;
    if (waitpid(pid, &st, WNOHANG) == pid) return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  return -1;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

double field(const std::string& text, const std::string& key) {
  const auto at = text.find(" " + key + " ");
  return at == std::string::npos ? -1 : std::stod(text.substr(at + key.size() + 2));
}

struct Row {
  std::string name, place, client;
  std::string secure;  // DDS Security directory of both processes, or none
  double p50 = -1, p99 = -1, mean = -1;
  int n = 0, lost = 0;
  long place_rss_kb = -1, client_rss_kb = -1;
};

Row measure(const std::string& self, const std::string& bin, const std::string& tmp, Row row, uint32_t domain, int samples,
            double rate) {
  std::vector<std::string> place_args{bin + "/pheromesh-place", "--scenario", kScenario, "--region", "0", "--dds",
                                      row.place, "--domain", std::to_string(domain), "--rate", std::to_string(rate),
                                      "--log-level", "warn"};
  std::vector<std::string> client_args{self, "client", "--dds", row.client, "--domain", std::to_string(domain),
                                       "--samples", std::to_string(samples)};
  if (!row.secure.empty()) {
    place_args.insert(place_args.end(), {"--secure", row.secure});
    client_args.insert(client_args.end(), {"--secure", row.secure});
  }
  const std::string tag = std::to_string(domain);
  const pid_t place = spawn(place_args, tmp + "/place-" + tag + ".log");
  const std::string client_out = tmp + "/client-" + tag + ".txt";
  const pid_t cl = spawn(client_args, client_out);
  const int rc = wait_for(cl, std::chrono::seconds(180));
  row.place_rss_kb = rss_kb(place);
  kill(place, SIGTERM);
  wait_for(place, std::chrono::seconds(20));
  const std::string text = slurp(client_out);
  if (rc != 0) {
    std::fprintf(stderr, "%s: client exited with %d:\n%s\n", row.name.c_str(), rc, text.c_str());
    return row;
  }
  row.p50 = field(text, "p50");
  row.p99 = field(text, "p99");
  row.mean = field(text, "mean");
  row.n = static_cast<int>(field(text, "n"));
  row.lost = static_cast<int>(field(text, "lost"));
  row.client_rss_kb = static_cast<long>(field(text, "rss_kb"));
  return row;
}

// ddsperf ping/pong (Cyclone, 12-byte samples, our one-host profile): median
// over its per-second reports of the round-trip p50 and p99 [us].
std::pair<double, double> ddsperf(const std::string& tmp, uint32_t domain) {
  const std::string uri = std::string("CYCLONEDDS_URI=file://") + PHEROMESH_SOURCE_DIR + "/deploy/dds/cyclone-onehost.xml";
  const std::string dom = std::to_string(domain);
  const pid_t pong = spawn({"ddsperf", "-i", dom, "-D", "8", "pong"}, tmp + "/pong.txt", {uri});
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const pid_t ping = spawn({"ddsperf", "-i", dom, "-D", "6", "ping"}, tmp + "/ping.txt", {uri});
  wait_for(ping, std::chrono::seconds(30));
  kill(pong, SIGTERM);
  wait_for(pong, std::chrono::seconds(10));
  std::istringstream in(slurp(tmp + "/ping.txt"));
  std::string line;
  std::vector<double> p50, p99;
  while (std::getline(in, line)) {
    if (line.find(" size 12 mean ") == std::string::npos) continue;
    auto us = [&](const std::string& key) {
      const auto at = line.find(key);
      return at == std::string::npos ? -1.0 : std::stod(line.substr(at + key.size()));
    };
    p50.push_back(us(" 50% "));
    p99.push_back(us(" 99% "));
  }
  return {percentile(p50, 0.5), percentile(p99, 0.5)};
}

// The table of `rows` beside ddsperf's round trip, and the JSON if asked.
void report(const std::vector<Row>& rows, double rtt50, double rtt99, double rate, const std::string& json_path) {
  std::printf(
      "\n| backend | p50 [us] | p99 [us] | mean [us] | p50 / ddsperf RTT p50 | samples | lost | place RSS [MiB] | "
      "uav-side RSS [MiB] |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  nlohmann::json j;
  for (const auto& r : rows) {
    std::printf("| %s | %.0f | %.0f | %.0f | %.1f | %d | %d | %.1f | %.1f |\n", r.name.c_str(), r.p50, r.p99, r.mean,
                rtt50 > 0 ? r.p50 / rtt50 : 0.0, r.n, r.lost, static_cast<double>(r.place_rss_kb) / 1024.0,
                static_cast<double>(r.client_rss_kb) / 1024.0);
    j["backends"].push_back({{"backend", r.name},
                             {"place", r.place},
                             {"client", r.client},
                             {"p50_us", r.p50},
                             {"p99_us", r.p99},
                             {"mean_us", r.mean},
                             {"samples", r.n},
                             {"lost", r.lost},
                             {"place_rss_kb", r.place_rss_kb},
                             {"client_rss_kb", r.client_rss_kb}});
  }
  std::printf("| ddsperf ping/pong round trip (cyclone, 12 B) | %.0f | %.0f | | 1.0 | | | | |\n", rtt50, rtt99);
  j["ddsperf_rtt_p50_us"] = rtt50;
  j["ddsperf_rtt_p99_us"] = rtt99;
  j["rate_hz"] = rate;
  if (!json_path.empty()) std::ofstream(json_path) << j.dump(2) << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Deposit -> tile-update latency and RSS per DDS backend (cyclone, fastdds, mixed), beside ddsperf",
               "pheromesh-bench-latency"};
  int samples = 400;
  double rate = 1000;
  uint32_t domain = 70;
  std::string json_path;
  app.add_option("--samples", samples, "Deposits timed per backend")->capture_default_str();
  app.add_option("--rate", rate, "Tick rate of the place agent [Hz]")->check(CLI::Range(1.0, 1000.0))->capture_default_str();
  app.add_option("--domain", domain, "DDS domain id of the benchmark")->check(CLI::Range(0, 232))->capture_default_str();
  app.add_option("--json", json_path, "Also write the figures as JSON to this file");
  bool security = false;
  app.add_flag("--security", security,
               "Per vendor: without DDS Security, then with it at protection none, sign and encrypt (instead of the "
               "vendor pairs)");
  std::string vendor, secure;
  auto* cl = app.add_subcommand("client", "(internal) the depositing side of one measurement");
  cl->add_option("--dds", vendor)->required();
  cl->add_option("--secure", secure);
  cl->add_option("--domain", domain);
  cl->add_option("--samples", samples);
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::warn);
  if (cl->parsed()) return client(vendor, domain, samples, secure);

  const std::string self = fs::read_symlink("/proc/self/exe").string();
  const std::string bin = fs::path(self).parent_path().string();
  const std::string tmp = (fs::temp_directory_path() / ("pheromesh-bench-latency-" + std::to_string(getpid()))).string();
  fs::create_directories(tmp);
  std::printf("deposit -> tile update, place agent at %.0f Hz (up to %.2f ms of tick wait included), %d samples each\n",
              rate, 1000.0 / rate, samples);
  std::vector<Row> plan = {{"cyclone", "cyclone", "cyclone", ""},
                           {"fastdds", "fastdds", "fastdds", ""},
                           {"mixed (cyclone place, fastdds uav)", "cyclone", "fastdds", ""},
                           {"mixed (fastdds place, cyclone uav)", "fastdds", "cyclone", ""}};
  if (security) {
    // The baseline and the three protections, per vendor, in this one run.
    plan.clear();
    for (const char* protection : {"none", "sign", "encrypt"}) {
      const std::string dir = tmp + "/sec-" + protection;
      const std::string cmd = bin + "/pheromesh security init " + dir + " --scenario " + kScenario +
                              " --probes 1 --protection " + protection + " > /dev/null";
      if (std::system(cmd.c_str()) != 0) {
        std::fprintf(stderr, "cannot make the identities: %s\n", cmd.c_str());
        return 3;
      }
    }
    for (const char* v : {"cyclone", "fastdds"}) {
      plan.push_back({std::string(v) + ", no security", v, v, ""});
      for (const char* protection : {"none", "sign", "encrypt"}) {
        plan.push_back({std::string(v) + ", secure, protection " + protection, v, v, tmp + "/sec-" + protection});
      }
    }
  }
  std::vector<Row> rows;
  for (const auto& p : plan) {
    rows.push_back(measure(self, bin, tmp, p, domain, samples, rate));
    // The next backend on a fresh domain, so no participant of this one lingers.
    ++domain;
  }
  const auto [rtt50, rtt99] = ddsperf(tmp, domain);
  report(rows, rtt50, rtt99, rate, json_path);
  fs::remove_all(tmp);
  bool ok = rtt50 > 0;
  for (const auto& r : rows) ok = ok && r.n > 0;
  return ok ? 0 : 1;
}
