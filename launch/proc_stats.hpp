// Resource figures of the processes a launcher started, read from Linux's
// /proc: the pure parsers of the file texts (unit-tested in
// tests/unit/test_proc_stats.cpp, header-only so that the unit tests need no
// cli library) and the readers that fetch those texts with plain open/read.
#pragma once

#include <sys/types.h>

#include <cstdint>
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

// --- readers ------------------------------------------------------------------

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

// This network namespace's IPv4 UDP counters (/proc/net/snmp): every socket
// of every process on the host (in this namespace), not only ours.
std::optional<UdpCounters> read_udp_counters();

}  // namespace pheromesh::cli
