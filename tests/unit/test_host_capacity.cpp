// bench/commands/host_capacity.hpp: what the host's hardware threads give
// when all are busy at once, as `bench scale` and `bench lockstep` print it.
#include "bench/commands/host_capacity.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

namespace pheromesh::cli {
namespace host_capacity_test {  // named: the unit tests build as one unity source

TEST(HostCapacity, TheWorkOfAllAtOnceIsAMultipleOfOnesRate) {
  // Worked by hand: alone 5.6 M rounds in 1 s; two at once 3.5 M each in
  // 1 s -> 7.0 M/s together = 1.25 x 5.6 M/s.
  const auto c = host_capacity_from({5'600'000, 1.0}, {{3'500'000, 1.0}, {3'500'000, 1.0}});
  EXPECT_EQ(c.threads, 2U);
  EXPECT_DOUBLE_EQ(c.one_rate, 5.6e6);
  EXPECT_DOUBLE_EQ(c.all_rate, 7.0e6);
  EXPECT_DOUBLE_EQ(c.ratio(), 1.25);
  EXPECT_EQ(c.describe(),
            "2 hardware threads busy at once did 1.25 times the work of one (a CPU-bound loop; near 2 where each has "
            "a core of its own)");
  // Rates, not rounds: a thread that ran 2 s counts its rounds per second.
  const auto d = host_capacity_from({1000, 0.5}, {{2000, 2.0}, {1000, 1.0}});
  EXPECT_DOUBLE_EQ(d.ratio(), 1.0);
  EXPECT_EQ(d.describe(),
            "2 hardware threads busy at once did 1.00 times the work of one (a CPU-bound loop; near 2 where each has "
            "a core of its own)");
}

TEST(HostCapacity, TheWakeUpIsNamedWhenMeasured) {
  auto c = host_capacity_from({5'600'000, 1.0}, {{3'500'000, 1.0}, {3'500'000, 1.0}});
  c.wake_us = 6.24;
  EXPECT_EQ(c.describe(),
            "2 hardware threads busy at once did 1.25 times the work of one (a CPU-bound loop; near 2 where each has "
            "a core of its own); a wake-up of another thread over a pipe took 6.2 µs");
}

TEST(HostCapacity, ItsJsonNamesTheThreadsTheRatioAndTheWakeUpOrNull) {
  auto c = host_capacity_from({5'600'000, 1.0}, {{3'500'000, 1.0}, {3'500'000, 1.0}});
  EXPECT_EQ(c.to_json().dump(), R"({"ratio":1.25,"threads":2,"wake_us":null})");
  c.wake_us = 6.5;
  EXPECT_EQ(c.to_json().dump(), R"({"ratio":1.25,"threads":2,"wake_us":6.5})");
}

TEST(HostCapacity, APingPongCountsTwoWakeUpsARoundTripAndEndsWithinItsBound) {
  const auto us = measure_wake_us(200, std::chrono::seconds(5));
  ASSERT_TRUE(us.has_value());
  EXPECT_GT(*us, 0.0);
  // A bound of nothing ends before the first round trip: nothing measured.
  EXPECT_FALSE(measure_wake_us(200, std::chrono::milliseconds(0)).has_value());
}

TEST(HostCapacity, NothingMeasuredSaysSoRatherThanAFigure) {
  const auto c = host_capacity_from({0, 0.0}, {{100, 1.0}});
  EXPECT_EQ(c.ratio(), 0.0);
  EXPECT_EQ(c.describe(), "host capacity not measured");
  const auto one = host_capacity_from({100, 1.0}, {{100, 1.0}});
  EXPECT_EQ(one.describe(),
            "1 hardware thread busy at once did 1.00 times the work of one (a CPU-bound loop; near 1 where each has a "
            "core of its own)");
}

TEST(HostCapacity, TheProbeRunsEveryThreadAndMeasuresSomething) {
  // Not a figure of speed: that the loop ran on the threads asked for.
  const auto c = measure_host_capacity(std::chrono::milliseconds(20), 2);
  EXPECT_EQ(c.threads, 2U);
  EXPECT_GT(c.one_rate, 0.0);
  EXPECT_GT(c.all_rate, 0.0);
  EXPECT_TRUE(c.wake_us.has_value());
  const auto d = measure_host_capacity(std::chrono::milliseconds(5));
  EXPECT_EQ(d.threads, std::max(1U, std::thread::hardware_concurrency()));
}

}  // namespace host_capacity_test
}  // namespace pheromesh::cli
