// Shared helpers of the integration tests (test_*.cpp): run pheromesh
// processes, read what they wrote, compare a lockstep run with the simulator.
// Each test uses its own DDS domain (see the list in integration_tests.cpp).
#pragma once

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace pheromesh::itest {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using nlohmann::json;


inline const std::string kBin = PHEROMESH_BIN_DIR;
inline const std::string kSrc = PHEROMESH_SOURCE_DIR;

struct Output {
  int exit_code = -1;
  std::string text;
};

// Runs a shell command, capturing stdout+stderr.
inline Output run(const std::string& cmd) {
  Output o;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (p == nullptr) return o;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), buf.size(), p) != nullptr) o.text += buf.data();
  const int st = pclose(p);
  o.exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  return o;
}

// A background process with its stdout in a file, in a process group of its
// own. Whoever holds it owns the process: if the test ends while it still
// runs (an ASSERT gave up, an exception), the destructor ends the group
// (SIGTERM, SIGKILL 45 s later) and reaps it, so a failed test leaves no
// swarm behind to answer the next test's samples. The 45 s are the
// launcher's own (pheromesh run puts each process in a group of its own and
// on SIGTERM stops the UAVs, then the place agents, then the ground station,
// each role SIGKILLed 10-15 s after its SIGTERM): SIGKILLed after 5 s, it
// left a Fast DDS UAV that ignored SIGTERM running on the test's domain,
// and the next test of that domain failed. A process the test has already
// reaped (wait_exit) is left alone.
struct Background {
  pid_t pid = -1;
  std::string out_path;

  Background() = default;
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;
  Background(Background&& o) noexcept : pid(std::exchange(o.pid, -1)), out_path(std::move(o.out_path)) {}
  Background& operator=(Background&& o) noexcept {
    if (this != &o) {
      end();
      pid = std::exchange(o.pid, -1);
      out_path = std::move(o.out_path);
    }
    return *this;
  }
  ~Background() { end(); }

 private:
  void end() noexcept {
    if (pid <= 0) return;
    // 0: ours and running. pid: it had exited, now reaped. -1 (ECHILD): reaped before.
    if (waitpid(pid, nullptr, WNOHANG) == 0) {
      kill(-pid, SIGTERM);
      const auto deadline = Clock::now() + std::chrono::seconds(45);
      bool reaped = false;
      while (Clock::now() < deadline && !(reaped = waitpid(pid, nullptr, WNOHANG) == pid)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      // The whole group, also when its leader went first but left a child
      // that ignored SIGTERM (no one left: ESRCH, harmless).
      kill(-pid, SIGKILL);
      if (!reaped) waitpid(pid, nullptr, 0);
    }
    pid = -1;
  }
};

inline Background start(const std::vector<std::string>& args, const std::string& out_path) {
  Background b;
  b.out_path = out_path;
  // Emptied here, before the fork: the child's freopen truncates it only
  // once it runs, and a test that waits for a line (wait_for_text) found
  // the previous run's at once. The Cells test then probed a swarm that
  // was not up yet: it failed in streaks, on every run after a first.
  { std::ofstream(out_path, std::ios::trunc); }
  b.pid = fork();
  if (b.pid == 0) {
    setpgid(0, 0);
    FILE* f = std::freopen(out_path.c_str(), "w", stdout);
    (void)f;
    std::vector<char*> argv;
    std::vector<std::string> copy = args;
    for (auto& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  if (b.pid > 0) setpgid(b.pid, b.pid);  // both sides: no window where the group does not exist yet
  return b;
}

inline int wait_exit(pid_t pid, std::chrono::seconds timeout) {
  const auto deadline = Clock::now() + timeout;
  while (Clock::now() < deadline) {
    int st = 0;
    if (waitpid(pid, &st, WNOHANG) == pid) return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  // Its whole group too (start() makes each a group leader): reaped here,
  // the Background handle no longer ends it, and a child left behind (a
  // monitor's ground station under `sh -c`) kept listening on the test's
  // domain for minutes and heard the next test's swarm. No group: ESRCH.
  kill(-pid, SIGKILL);
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  return -1;
}

inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline json read_metrics(const std::string& dir) {
  std::ifstream in(dir + "/metrics.json");
  json j;
  if (in) in >> j;
  return j;
}

// The folder of a test's output: OUT/<backend>/NAME when PHEROMESH_DDS picks a
// backend, so each backend's run of a test keeps its own logs for a post-mortem.
inline std::string out_path(const std::string& name) {
  const char* backend = std::getenv("PHEROMESH_DDS");
  return (fs::path(PHEROMESH_TEST_OUT_DIR) / (backend != nullptr && *backend != '\0' ? backend : "any") / name).string();
}

// out_path(NAME), emptied and created.
inline std::string out_dir(const std::string& name) {
  const fs::path d = out_path(name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

inline std::string pheromesh_run(const std::string& scenario, const std::string& out, int domain, const std::string& extra) {
  return kBin + "/pheromesh run " + kSrc + "/scenarios/" + scenario + " --out " + out + " --domain " +
         std::to_string(domain) + " --progress 0.5 " + extra;
}

// `pheromesh run` in the background; its output goes to OUT.txt beside OUT.
inline Background start_run(const std::string& scenario, const std::string& out, int domain, const std::string& extra) {
  return start({"/bin/sh", "-c", pheromesh_run(scenario, out, domain, extra) + " 2>&1"}, out + ".txt");
}

// Waits until `path` holds `text` (bounded).
inline bool wait_for_text(const std::string& path, const std::string& text, std::chrono::seconds bound) {
  const auto deadline = std::chrono::steady_clock::now() + bound;
  while (std::chrono::steady_clock::now() < deadline) {
    if (slurp(path).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

// The tick of the ground station's last progress line ("[ground] tick    12 |
// ...") in `path`; 0 before the first.
inline uint32_t progress_tick(const std::string& path) {
  const std::string text = slurp(path);
  const auto at = text.rfind("] tick ");
  if (at == std::string::npos) return 0;
  return static_cast<uint32_t>(std::strtoul(text.c_str() + at + 7, nullptr, 10));
}

// Waits until the ground station's progress lines in `path` reach `tick`
// (bounded); false if they did not.
inline bool wait_for_tick(const std::string& path, uint32_t tick, std::chrono::seconds bound) {
  const auto deadline = Clock::now() + bound;
  while (progress_tick(path) < tick && Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return progress_tick(path) >= tick;
}

// Coverage recorded at the last progress line at or before `tick`.
inline double coverage_at(const json& m, uint32_t tick) {
  double c = 0;
  for (const auto& e : m["coverage_series"]) {
    if (e[0].get<uint32_t>() <= tick) c = e[1].get<double>();
  }
  return c;
}

// The metrics a deposit count depends on, without the long series (CI cuts
// the middle of a long failure message).
inline std::string accounting_summary(const json& m) {
  json j = json::object();
  for (auto it = m.begin(); it != m.end(); ++it) {
    const std::string& k = it.key();
    if (k.rfind("deposits", 0) == 0 || k.rfind("uav_", 0) == 0 || k.rfind("place", 0) == 0 || k == "processes" ||
        k.find("killed") != std::string::npos || k == "faults") {
      j[k] = it.value();
    }
  }
  return j.dump(1);
}

inline void expect_accounting(const json& m) {
  EXPECT_GT(m["deposits_sent"].get<uint64_t>(), 0U);
  EXPECT_EQ(m["deposits_sent"].get<uint64_t>(),
            m["deposits_applied"].get<uint64_t>() + m["deposits_rejected"].get<uint64_t>())
      << accounting_summary(m);
}


// `run_args` go to `pheromesh run` only (e.g. --dds), `args` to run and sim.
// What a lockstep run wrote to `run_out` (with --tracks) is what `pheromesh
// sim` writes for `scenario` and `args`, byte for byte.
inline void expect_same_as_sim(const std::string& run_out, const std::string& scenario, const std::string& args,
                               const std::string& tag) {
  const std::string sim_out = out_dir(tag + "-sim");
  const Output s =
      run(kBin + "/pheromesh sim " + kSrc + "/scenarios/" + scenario + " --quiet --tracks --out " + sim_out + " " + args);
  ASSERT_EQ(s.exit_code, 0) << s.text;
  const json a = read_metrics(run_out);
  const json b = read_metrics(sim_out);
  for (const char* key : {"policy", "ticks", "uavs", "coverage", "covered_cells", "targets_found", "acquisition_ticks",
                          "revisit_response_ticks", "leader_arrival_tick", "deposits_sent", "deposits_applied", "deposits_rejected", "field"}) {
    // leader_arrival_tick: absent from both without a leader.
    EXPECT_EQ(a.value(key, json()), b.value(key, json())) << key;
  }
  EXPECT_EQ(a["deposits_rejected"], 0);
  // Where every UAV ended, in which role.
  ASSERT_EQ(a["uav_status"].size(), b["uav_status"].size());
  for (const auto& [id, u] : b["uav_status"].items()) {
    for (const char* key : {"x", "y", "role"}) EXPECT_EQ(a["uav_status"][id][key], u[key]) << "uav " << id << " " << key;
  }
  const std::string field_run = slurp(run_out + "/final_field.txt");
  EXPECT_GT(field_run.size(), 1000U);
  EXPECT_TRUE(field_run == slurp(sim_out + "/final_field.txt")) << "final pheromone fields differ";
  EXPECT_EQ(field_run.find("nan"), std::string::npos);
  // The tidy files (docs/outputs.md): byte for byte, every tick.
  for (const char* file : {"series.csv", "tracks.csv", "final_field.csv"}) {
    const std::string from_run = slurp(run_out + "/" + file);
    EXPECT_GT(std::count(from_run.begin(), from_run.end(), '\n'), 10) << file;
    EXPECT_TRUE(from_run == slurp(sim_out + "/" + file)) << file << " differs: see " << run_out << " and " << sim_out;
  }
}

inline void expect_lockstep_matches_sim(const std::string& scenario, const std::string& args, int domain, const std::string& tag,
                                        const std::string& run_args = "") {
  const std::string run_out = out_dir(tag + "-lockstep");
  const Output r = run(pheromesh_run(scenario, run_out, domain, "--clock lockstep --tracks " + args + " " + run_args));
  {
    // The launcher's and the ground station's output, for a failure's post-mortem.
    std::ofstream keep(run_out + "/launcher.txt");
    keep << r.text;
  }
  ASSERT_EQ(r.exit_code, 0) << r.text;
  expect_same_as_sim(run_out, scenario, args, tag);
}

}  // namespace pheromesh::itest
