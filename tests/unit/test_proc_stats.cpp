// The /proc parsers of the launcher's resource accounting (launch/proc_stats.hpp,
// header-only for these tests), on texts copied from a Linux 6.x host.
#include <gtest/gtest.h>

#include <unistd.h>
#include <ctime>
#include <vector>

#include "launch/proc_stats.hpp"

namespace pheromesh::cli {
namespace {

constexpr const char* kSmapsRollup =
    "55a6df237000-7ffdc032d000 ---p 00000000 00:00 0                          [rollup]\n"
    "Rss:               21660 kB\n"
    "Pss:                8510 kB\n"
    "Pss_Dirty:          6112 kB\n"
    "Pss_Anon:           6112 kB\n"
    "Pss_File:           2398 kB\n"
    "Pss_Shmem:             0 kB\n"
    "Shared_Clean:      13028 kB\n";

TEST(ProcStats, SmapsRollupGivesRssAndPssNotPssDirty) {
  const auto r = parse_smaps_rollup(kSmapsRollup);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->rss_kib, 21660U);
  EXPECT_EQ(r->pss_kib, 8510U);
}

TEST(ProcStats, SmapsRollupOfAVanishedProcessIsNothing) {
  EXPECT_FALSE(parse_smaps_rollup("").has_value());
  // A guard that the parser does not take Pss_Dirty for Pss.
  EXPECT_FALSE(parse_smaps_rollup("Rss: 10 kB\nPss_Dirty: 5 kB\n").has_value());
}

TEST(ProcStats, StatusGivesThreadsAndState) {
  const char* status =
      "Name:\tpheromesh-uav\nUmask:\t0022\nState:\tS (sleeping)\nTgid:\t4242\nVmRSS:\t   21660 kB\nThreads:\t17\n"
      "SigQ:\t0/62811\n";
  EXPECT_EQ(parse_status_threads(status), std::optional<uint64_t>(17));
  EXPECT_EQ(parse_status_state(status), 'S');
  EXPECT_EQ(parse_status_state("Name:\tx\nState:\tZ (zombie)\nThreads:\t1\n"), 'Z');
  EXPECT_FALSE(parse_status_threads("Name:\tx\n").has_value());
  EXPECT_EQ(parse_status_state("Name:\tx\n"), '\0');
}

TEST(ProcStats, SnmpUdpCountersAreFoundByColumnNameAndUdpLiteIsIgnored) {
  const char* snmp =
      "Ip: Forwarding DefaultTTL InReceives\nIp: 1 64 1234\n"
      "Udp: InDatagrams NoPorts InErrors OutDatagrams RcvbufErrors SndbufErrors InCsumErrors IgnoredMulti MemErrors\n"
      "Udp: 123456789012 4 0 98765 0 0 0 7 0\n"
      "UdpLite: InDatagrams NoPorts InErrors OutDatagrams RcvbufErrors SndbufErrors InCsumErrors IgnoredMulti "
      "MemErrors\n"
      "UdpLite: 1 2 3 4 5 6 7 8 9\n";
  const auto c = parse_snmp_udp(snmp);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->in_datagrams, 123456789012U);
  EXPECT_EQ(c->out_datagrams, 98765U);
  // Columns in another order are still found by name.
  const auto swapped = parse_snmp_udp("Udp: OutDatagrams InDatagrams\nUdp: 5 9\n");
  ASSERT_TRUE(swapped.has_value());
  EXPECT_EQ(swapped->in_datagrams, 9U);
  EXPECT_EQ(swapped->out_datagrams, 5U);
}

TEST(ProcStats, SnmpWithoutUdpValuesIsNothing) {
  EXPECT_FALSE(parse_snmp_udp("").has_value());
  EXPECT_FALSE(parse_snmp_udp("Udp: InDatagrams OutDatagrams\n").has_value());
  EXPECT_FALSE(parse_snmp_udp("UdpLite: InDatagrams OutDatagrams\nUdpLite: 1 2\n").has_value());
  EXPECT_FALSE(parse_snmp_udp("Udp: InDatagrams OutDatagrams\nUdp: 1 x\n").has_value());
}

TEST(ProcStats, StatGivesTheNameAndUserPlusSystemTicksEvenWithBlanksAndParenthesesInTheName) {
  // Fields 14 (utime) and 15 (stime), counted after the last ')'.
  const auto s = parse_stat_cpu("4242 (dq.builtins) S 1 4242 4242 0 -1 4194560 300 0 0 0 17 5 0 0 20 0 9 0 123\n");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->comm, "dq.builtins");
  EXPECT_EQ(s->ticks, 22U);
  const auto odd = parse_stat_cpu("7 (a (b) c) R 1 7 7 0 -1 0 0 0 0 0 100 250 0 0 20 0 1 0 5");
  ASSERT_TRUE(odd.has_value());
  EXPECT_EQ(odd->comm, "a (b) c");
  EXPECT_EQ(odd->ticks, 350U);
  EXPECT_FALSE(parse_stat_cpu("7 (short) R 1 2").has_value());
  EXPECT_FALSE(parse_stat_cpu("no parentheses").has_value());
}

TEST(ProcStats, SchedstatGivesTheRunTimeInNanoseconds) {
  EXPECT_EQ(parse_schedstat_run_ns("145489 3129691 2\n"), 145489U);
  EXPECT_FALSE(parse_schedstat_run_ns("").has_value());
  EXPECT_FALSE(parse_schedstat_run_ns("12x 3 4").has_value());
}

TEST(ProcStats, ClockTicksBecomeNanoseconds) {
  EXPECT_EQ(clock_ticks_ns(22, 100), 220'000'000U);  // 22 ticks of 10 ms
  EXPECT_EQ(clock_ticks_ns(3, 1000), 3'000'000U);
  EXPECT_EQ(clock_ticks_ns(5, 0), 0U);  // no clock rate: no figure, not a division by zero
}

TEST(ProcStats, AProcessesCpuFromItsStatAgreesWithItsThreadsWithinTheClockTicks) {
  // This process burns 100 ms of CPU in this thread between two looks of
  // each kind: /proc/PID/stat counts it in 10 ms clock ticks (up to one tick
  // lost at each look), the threads' schedstat exactly.
  const pid_t self = getpid();
  const auto p0 = sample_cpu(self, CpuDetail::Process);
  const auto t0 = sample_cpu(self, CpuDetail::Threads);
  ASSERT_TRUE(p0 && t0);
  EXPECT_FALSE(p0->per_thread);
  EXPECT_TRUE(p0->thread_ns.empty());
  EXPECT_TRUE(t0->per_thread);
  EXPECT_FALSE(t0->thread_ns.empty());
  const auto thread_cpu_ns = [] {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<uint64_t>(ts.tv_sec) * 1'000'000'000ULL + static_cast<uint64_t>(ts.tv_nsec);
  };
  const uint64_t start = thread_cpu_ns();
  volatile uint64_t sink = 0;
  while (thread_cpu_ns() - start < 100'000'000ULL) sink = sink + 1;
  const auto p1 = sample_cpu(self, CpuDetail::Process);
  const auto t1 = sample_cpu(self, CpuDetail::Threads);
  ASSERT_TRUE(p1 && t1);
  const auto dp = static_cast<int64_t>(p1->cpu_ns - p0->cpu_ns);
  const auto dt = static_cast<int64_t>(t1->cpu_ns - t0->cpu_ns);
  EXPECT_GE(dt, 100'000'000);
  EXPECT_NEAR(static_cast<double>(dp), static_cast<double>(dt), 25e6)
      << "stat " << dp << " ns, threads " << dt << " ns";
}

TEST(ProcStats, AThreadsGroupIsItsNameWithoutATrailingNumber) {
  EXPECT_EQ(thread_group("recvUC12"), "recvUC");
  EXPECT_EQ(thread_group("tev"), "tev");
  EXPECT_EQ(thread_group("dq.builtins"), "dq.builtins");
  EXPECT_EQ(thread_group("42"), "42");  // all digits: the name stays
}

TEST(ProcStats, TheResourceSampleTakesKOfNUavsSpreadEvenly) {
  const auto taken = [](std::size_t n, std::size_t k) {
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < n; ++i) {
      if (evenly_taken(i, n, k)) out.push_back(i);
    }
    return out;
  };
  // 10 of 4: the first of each run of 10 / 4 = 2.5 (floor(i * 4 / 10) steps at 0, 3, 5, 8).
  EXPECT_EQ(taken(10, 4), (std::vector<std::size_t>{0, 3, 5, 8}));
  EXPECT_EQ(taken(3, 4), (std::vector<std::size_t>{0, 1, 2})) << "fewer than k: every one";
  EXPECT_EQ(taken(4, 4), (std::vector<std::size_t>{0, 1, 2, 3}));
  EXPECT_EQ(taken(1517, 200).size(), 200U);
  EXPECT_EQ(taken(2000, 200).size(), 200U);
  EXPECT_EQ(taken(2000, 200)[1], 10U);
}

}  // namespace
}  // namespace pheromesh::cli
