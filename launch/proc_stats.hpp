// Resource figures of the processes a launcher started, read from Linux's
// /proc: the pure parsers of the file texts (unit-tested in
// tests/unit/test_proc_stats.cpp, header-only so that the unit tests need no
// cli library) and the readers that fetch those texts with plain open/read.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace pheromesh::cli {

// --- pure parsers -------------------------------------------------------------

namespace detail {

// The unsigned number after "Key:" on the line that starts with `key` + ':'
// (leading blanks skipped, the unit ignored), or nothing.
inline std::optional<uint64_t> field_after(std::string_view text, std::string_view key) {
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    const std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    if (line.size() <= key.size() || line.substr(0, key.size()) != key || line[key.size()] != ':') continue;
    std::size_t i = key.size() + 1;
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i >= line.size() || line[i] < '0' || line[i] > '9') return std::nullopt;
    uint64_t v = 0;
    for (; i < line.size() && line[i] >= '0' && line[i] <= '9'; ++i) v = v * 10 + static_cast<uint64_t>(line[i] - '0');
    return v;
  }
  return std::nullopt;
}

}  // namespace detail

// /proc/PID/smaps_rollup: "Rss:  1234 kB", "Pss:  567 kB" (both in kB).
struct SmapsRollup {
  uint64_t rss_kib = 0;
  uint64_t pss_kib = 0;
};
inline std::optional<SmapsRollup> parse_smaps_rollup(std::string_view text) {
  const auto rss = detail::field_after(text, "Rss");
  const auto pss = detail::field_after(text, "Pss");
  if (!rss || !pss) return std::nullopt;
  return SmapsRollup{*rss, *pss};
}

// /proc/PID/status: "Threads:\t12".
inline std::optional<uint64_t> parse_status_threads(std::string_view text) {
  return detail::field_after(text, "Threads");
}

// /proc/PID/status: "State:\tZ (zombie)" -> 'Z'; 0 if there is no State line.
inline char parse_status_state(std::string_view text) {
  for (std::size_t pos = 0; pos < text.size();) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    if (line.substr(0, 6) != "State:") continue;
    line.remove_prefix(6);
    const std::size_t b = line.find_first_not_of(" \t");
    return b == std::string_view::npos ? '\0' : line[b];
  }
  return '\0';
}

// /proc/net/snmp: a header line "Udp: InDatagrams NoPorts ... OutDatagrams ..."
// followed by a value line "Udp: 123 4 ..." (the "UdpLite:" pair is another
// protocol and is not read). The columns are found by name.
struct UdpCounters {
  uint64_t in_datagrams = 0;
  uint64_t out_datagrams = 0;
};
inline std::optional<UdpCounters> parse_snmp_udp(std::string_view text) {
  constexpr std::string_view kPrefix = "Udp:";
  std::optional<std::string_view> header, values;
  std::size_t pos = 0;
  while (pos < text.size() && !values) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    const std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    if (line.substr(0, kPrefix.size()) != kPrefix) continue;
    (header ? values : header) = line.substr(kPrefix.size());
  }
  if (!header || !values) return std::nullopt;
  // Walks both lines word by word, in step.
  auto next_word = [](std::string_view& s) {
    const std::size_t b = s.find_first_not_of(" \t");
    if (b == std::string_view::npos) {
      s = {};
      return std::string_view{};
    }
    const std::size_t e = s.find_first_of(" \t", b);
    const std::string_view w = s.substr(b, e == std::string_view::npos ? std::string_view::npos : e - b);
    s = e == std::string_view::npos ? std::string_view{} : s.substr(e);
    return w;
  };
  std::optional<uint64_t> in, out;
  std::string_view h = *header, v = *values;
  for (;;) {
    const std::string_view name = next_word(h), value = next_word(v);
    if (name.empty() || value.empty()) break;
    uint64_t n = 0;
    bool digits = true;
    for (char c : value) {
      if (c < '0' || c > '9') {
        digits = false;
        break;
      }
      n = n * 10 + static_cast<uint64_t>(c - '0');
    }
    if (!digits) return std::nullopt;
    if (name == "InDatagrams") in = n;
    if (name == "OutDatagrams") out = n;
  }
  if (!in || !out) return std::nullopt;
  return UdpCounters{*in, *out};
}

// /proc/PID/stat (and /proc/PID/task/TID/stat): "pid (comm) state ..."; the
// comm may hold blanks and parentheses, so the fields are counted after the
// last ')'. utime and stime are fields 14 and 15 [clock ticks].
struct StatCpu {
  std::string comm;
  uint64_t ticks = 0;  // utime + stime
};
inline std::optional<StatCpu> parse_stat_cpu(std::string_view text) {
  const std::size_t open = text.find('('), close = text.rfind(')');
  if (open == std::string_view::npos || close == std::string_view::npos || close < open) return std::nullopt;
  StatCpu s{std::string(text.substr(open + 1, close - open - 1)), 0};
  // After ") ": field 3 (state) is the first; utime is the 12th from there.
  std::string_view rest = text.substr(close + 1);
  uint64_t values[2] = {0, 0};
  int field = 2, got = 0;
  std::size_t i = 0;
  while (i < rest.size() && got < 2) {
    while (i < rest.size() && rest[i] == ' ') ++i;
    if (i >= rest.size()) break;
    ++field;
    const std::size_t b = i;
    while (i < rest.size() && rest[i] != ' ' && rest[i] != '\n') ++i;
    if (field == 14 || field == 15) {
      uint64_t v = 0;
      for (std::size_t k = b; k < i; ++k) {
        if (rest[k] < '0' || rest[k] > '9') return std::nullopt;
        v = v * 10 + static_cast<uint64_t>(rest[k] - '0');
      }
      values[got++] = v;
    }
  }
  if (got < 2) return std::nullopt;
  s.ticks = values[0] + values[1];
  return s;
}

// /proc/PID/task/TID/schedstat: "run_ns wait_ns timeslices": the time the
// thread ran [ns], exact (utime and stime are counted in 10 ms ticks, too
// coarse for a UAV's threads over seconds).
inline std::optional<uint64_t> parse_schedstat_run_ns(std::string_view text) {
  uint64_t v = 0;
  std::size_t i = 0;
  for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i) v = v * 10 + static_cast<uint64_t>(text[i] - '0');
  if (i == 0 || (i < text.size() && text[i] != ' ' && text[i] != '\n')) return std::nullopt;
  return v;
}

// A thread's group in the CPU breakdown: its name without a trailing number
// (Cyclone's "recvUC1" and "recvUC2" are one group, "recvUC").
inline std::string thread_group(std::string_view comm) {
  std::size_t n = comm.size();
  while (n > 0 && comm[n - 1] >= '0' && comm[n - 1] <= '9') --n;
  return std::string(n == 0 ? comm : comm.substr(0, n));
}

// --- readers ------------------------------------------------------------------

// Of n items in order, whether the i-th is one of k spread evenly over them
// (every one when n <= k): the first of each run of n / k.
inline bool evenly_taken(std::size_t i, std::size_t n, std::size_t k) {
  return n <= k || i == 0 || (i * k) / n != ((i - 1) * k) / n;
}

// The whole of a small /proc file (up to 64 KiB) with open/read, or nothing
// if it cannot be opened (the process has gone, or no such file).
std::optional<std::string> read_small_file(const char* path);

// One look at a running process.
struct ProcessSample {
  std::optional<double> pss_mib, rss_mib;  // smaps_rollup [MiB]
  std::optional<uint64_t> threads;         // status
};
// Nothing if the process has vanished (neither file readable) or is a zombie
// waiting to be reaped.
std::optional<ProcessSample> sample_process(pid_t pid);

// The CPU a running process used so far, and how often it was switched
// out: /proc/PID/status, and either each thread's task/TID/stat (its name)
// and schedstat (its time, exact), or only /proc/PID/stat (the process's
// utime + stime, which the kernel scales to its exact run time, in clock
// ticks). The second is two files a process instead of two per thread: a
// pass over 2000 UAV processes of 6 threads each took 21.7 s on a host the
// swarm kept busy (docs/benchmarks.md, "Where a UAV tick goes").
enum class CpuDetail { Threads, Process };
struct CpuSample {
  uint64_t cpu_ns = 0;                        // the threads' run time, summed [ns]
  uint64_t ctx_voluntary = 0;                 // status: voluntary_ctxt_switches (it waited)
  uint64_t ctx_involuntary = 0;               // status: nonvoluntary_ctxt_switches (it was preempted)
  std::map<std::string, uint64_t> thread_ns;  // thread_group(name) -> run time of those threads [ns]
  bool per_thread = true;                     // thread_ns was read (CpuDetail::Threads)
};
std::optional<CpuSample> sample_cpu(pid_t pid, CpuDetail detail = CpuDetail::Threads);

// Clock ticks (utime, stime) to nanoseconds at `ticks_per_s` (sysconf
// _SC_CLK_TCK, 100 on Linux).
inline uint64_t clock_ticks_ns(uint64_t ticks, uint64_t ticks_per_s) {
  return ticks_per_s == 0 ? 0 : ticks * (1'000'000'000ULL / ticks_per_s);
}

// This network namespace's IPv4 UDP counters (/proc/net/snmp): every socket
// of every process on the host (in this namespace), not only ours.
std::optional<UdpCounters> read_udp_counters();

}  // namespace pheromesh::cli
