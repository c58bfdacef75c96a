#include "bench_floor.hpp"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "launch/child_spawn.hpp"
#include "launch/launcher.hpp"
#include "pheromesh/bus/bus.hpp"
#include "pheromesh/core/conductor.hpp"
#include "pheromesh/runtime/process.hpp"

namespace pheromesh::cli {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// A RegionCount is two 32-bit words on the wire; the lists are bounded by
// MAX_REGION_COUNTS (idl/).
constexpr std::size_t kRegionCountBytes = 8;

std::vector<core::RegionCount> padding(std::size_t bytes) {
  const std::size_t n = std::min(bytes / kRegionCountBytes, core::kMaxRegionCounts);
  std::vector<core::RegionCount> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = {static_cast<core::RegionId>(i), 1};
  return out;
}

// Nanoseconds every thread of `pid` has run (the first field of each
// /proc/<pid>/task/<tid>/schedstat); nullopt if none could be read.
std::optional<double> cpu_ns(pid_t pid) {
  std::error_code ec;
  const fs::path tasks = "/proc/" + std::to_string(pid) + "/task";
  double sum = 0;
  bool any = false;
  for (const auto& t : fs::directory_iterator(tasks, ec)) {
    std::ifstream in(t.path() / "schedstat");
    double ns = 0;
    if (in >> ns) {
      sum += ns;
      any = true;
    }
  }
  if (!any) return std::nullopt;
  return sum;
}

// `pheromesh bench lockstep-echo` over `dds`, its output into `log`; -1
// (and `error` says why) if it could not be started.
pid_t spawn_echo(const FloorOptions& o, const std::string& dds, const fs::path& log, std::string& error) {
  const std::string exe = executable_dir() + "/pheromesh";
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    error = "cannot write " + log.string();
    return -1;
  }
  const pid_t child = spawn_logged_child(exe,
                                         {exe, "bench", "lockstep-echo", "--dds", dds, "--domain",
                                          std::to_string(o.domain), "--answer-bytes", std::to_string(o.up_bytes)},
                                         fd, true);
  ::close(fd);
  if (child < 0) error = "cannot start the echo process";
  return child;
}

// The echo ends at the Stop it was sent; killed after 5 s if it did not.
void reap_echo(pid_t child) {
  int status = 0;
  for (int i = 0; i < 100 && waitpid(child, &status, WNOHANG) == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (waitpid(child, &status, WNOHANG) == 0) {
    kill(child, SIGKILL);
    waitpid(child, &status, 0);
  }
}

}  // namespace

Floor measure_floor(const FloorOptions& o) {
  Floor f;
  f.pairing = o.pairing;
  const std::string mine = o.pairing == "fastdds" ? "fastdds" : "cyclone";
  const std::string theirs = o.pairing == "cyclone" ? "cyclone" : "fastdds";
  bus::BusOptions bo;
  bo.process_name = "bench-floor";
  bo.domain = o.domain;
  auto made = bus::make_bus(mine, bo);
  if (!made) {
    f.error = made.error().message;
    return f;
  }
  auto& b = *made.value();
  b.subscribe_phase_done();
  const fs::path log = fs::path(o.out_dir) / ("echo-" + o.pairing + ".log");
  const pid_t child = spawn_echo(o, theirs, log, f.error);
  if (child < 0) return f;
  core::ClockMsg c;
  c.phase = static_cast<uint8_t>(core::ClockPhase::Uav);
  c.deposits = padding(o.down_bytes);
  f.down_bytes = c.deposits.size() * kRegionCountBytes;
  f.up_bytes = std::min(o.up_bytes / kRegionCountBytes, core::kMaxRegionCounts) * kRegionCountBytes;
  std::vector<core::PhaseDoneMsg> dones;
  // One ping: true when the answer of `tick` came before `bound`.
  const auto ping = [&](uint32_t tick, std::chrono::milliseconds bound) {
    c.tick = tick;
    b.publish_clock(c);
    const auto deadline = Clock::now() + bound;
    while (Clock::now() < deadline) {
      dones.clear();
      b.take_phase_done(dones);
      for (const auto& d : dones) {
        if (d.tick == tick) return true;
      }
      b.wait({bus::TopicKind::PhaseDone}, deadline);
    }
    return false;
  };
  // Discovery: tick 0 until it is answered (30 s at most).
  bool up = false;
  for (int i = 0; i < 300 && !up && !runtime::shutdown_requested(); ++i) up = ping(0, std::chrono::milliseconds(100));
  if (!up) {
    f.error = "the echo process did not answer within 30 s (" + log.string() + ")";
  } else {
    std::vector<double> rtt;
    const auto cpu0_self = cpu_ns(getpid()), cpu0_child = cpu_ns(child);
    for (uint32_t i = 1; i <= o.pings && !runtime::shutdown_requested(); ++i) {
      const auto t0 = Clock::now();
      if (ping(i, std::chrono::seconds(2))) {
        rtt.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      } else {
        ++f.lost;
      }
    }
    const auto cpu1_self = cpu_ns(getpid()), cpu1_child = cpu_ns(child);
    if (cpu0_self && cpu0_child && cpu1_self && cpu1_child && !rtt.empty()) {
      f.cpu_ms = (*cpu1_self - *cpu0_self + *cpu1_child - *cpu0_child) / 1e6 / static_cast<double>(rtt.size());
    }
    f.rtt_ms = core::summarize(std::move(rtt));
  }
  b.publish_clock(core::LockstepConductor::stop(0));
  reap_echo(child);
  return f;
}

int run_lockstep_echo(const LockstepEchoOptions& o) {
  bus::BusOptions bo;
  bo.process_name = "bench-lockstep-echo";
  bo.domain = o.domain;
  auto made = bus::make_bus(o.dds, bo);
  if (!made) {
    spdlog::error("{}", made.error().message);
    return 2;
  }
  auto& b = *made.value();
  b.subscribe_clock();
  std::vector<core::ClockMsg> clocks;
  core::PhaseDoneMsg answer{core::process_key(core::kRoleUav, 0), 0, 0, 0, padding(o.answer_bytes)};
  const auto deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.timeout_s));
  while (Clock::now() < deadline && !runtime::shutdown_requested()) {
    clocks.clear();
    b.take_clock(clocks);
    for (const auto& c : clocks) {
      if (c.phase == static_cast<uint8_t>(core::ClockPhase::Stop)) return 0;
      answer.tick = c.tick;
      answer.phase = c.phase;
      b.publish_phase_done(answer);
    }
    b.wait({bus::TopicKind::Clock}, std::min(deadline, Clock::now() + std::chrono::milliseconds(100)));
  }
  return runtime::shutdown_requested() ? 0 : 1;
}

}  // namespace pheromesh::cli
