#include "host_capacity.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <thread>

namespace pheromesh::cli {
namespace {

using Clock = std::chrono::steady_clock;

// A round: a few thousand steps of a xorshift generator, all in registers,
// so that the loop measures the thread's share of a core, not the memory.
uint64_t one_round(uint64_t x) {
  for (int i = 0; i < 4096; ++i) {
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
  }
  return x;
}

LoopRun run_loop(std::chrono::milliseconds each, std::atomic<uint64_t>& sink) {
  LoopRun r;
  uint64_t x = 0x9E3779B97F4A7C15ULL;
  const auto t0 = Clock::now();
  const auto end = t0 + each;
  auto now = t0;
  while (now < end) {
    x = one_round(x);
    ++r.rounds;
    now = Clock::now();
  }
  r.seconds = std::chrono::duration<double>(now - t0).count();
  sink.fetch_xor(x, std::memory_order_relaxed);  // the result is used: the loop stays
  return r;
}

double rate(const LoopRun& r) { return r.seconds > 0 ? static_cast<double>(r.rounds) / r.seconds : 0.0; }

}  // namespace

std::string HostCapacity::describe() const {
  if (ratio() <= 0) return "host capacity not measured";
  return fmt::format(
      "{} hardware thread{} busy at once did {:.2f} times the work of one (a CPU-bound loop; near {} where each has a "
      "core of its own){}",
      threads, threads == 1 ? "" : "s", ratio(), threads,
      wake_us ? fmt::format("; a wake-up of another thread over a pipe took {:.1f} µs", *wake_us) : "");
}

nlohmann::json HostCapacity::to_json() const {
  nlohmann::json j{{"threads", threads}, {"ratio", ratio()}, {"wake_us", nullptr}};
  if (wake_us) j["wake_us"] = *wake_us;
  return j;
}

std::optional<double> measure_wake_us(uint32_t round_trips, std::chrono::milliseconds bound) {
  int there[2];
  int back[2];
  if (pipe(there) != 0) return std::nullopt;
  if (pipe(back) != 0) {
    close(there[0]);
    close(there[1]);
    return std::nullopt;
  }
  // The other thread answers each byte until its pipe closes.
  std::thread echo([&] {
    char c = 0;
    while (read(there[0], &c, 1) == 1) {
      if (write(back[1], &c, 1) != 1) break;
    }
  });
  uint32_t done = 0;
  const auto t0 = Clock::now();
  const auto end = t0 + bound;
  char c = 'w';
  while (done < round_trips && Clock::now() < end) {
    if (write(there[1], &c, 1) != 1 || read(back[0], &c, 1) != 1) break;
    ++done;
  }
  const double us = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
  close(there[1]);  // the echo's read ends
  echo.join();
  close(there[0]);
  close(back[0]);
  close(back[1]);
  if (done == 0) return std::nullopt;
  return us / (2.0 * done);
}

HostCapacity host_capacity_from(const LoopRun& alone, const std::vector<LoopRun>& together) {
  HostCapacity c;
  c.threads = static_cast<unsigned>(together.size());
  c.one_rate = rate(alone);
  for (const auto& r : together) c.all_rate += rate(r);
  return c;
}

HostCapacity measure_host_capacity(std::chrono::milliseconds each, unsigned threads) {
  if (threads == 0) threads = std::max(1U, std::thread::hardware_concurrency());
  std::atomic<uint64_t> sink{0};
  const LoopRun alone = run_loop(each, sink);
  std::vector<LoopRun> together(threads);
  std::atomic<unsigned> ready{0};
  std::vector<std::thread> workers;
  workers.reserve(threads);
  for (unsigned i = 0; i < threads; ++i) {
    workers.emplace_back([&, i] {
      // Every thread starts its loop once all exist, so that they overlap.
      ready.fetch_add(1);
      while (ready.load() < threads) std::this_thread::yield();
      together[i] = run_loop(each, sink);
    });
  }
  for (auto& w : workers) w.join();
  HostCapacity c = host_capacity_from(alone, together);
  c.wake_us = measure_wake_us(20000, std::chrono::seconds(2));
  return c;
}

}  // namespace pheromesh::cli
