// KeepAlivePace (bus/src/vendor_pace.hpp): when a transport asserts its
// manual-by-topic writers, with the time passed in.
#include <gtest/gtest.h>

#include <vector>

#include "vendor_pace.hpp"

namespace pheromesh::bus {
namespace {

using std::chrono::milliseconds;

struct Rounds {
  KeepAlivePace pace{milliseconds(1000)};
  KeepAlivePace::Clock::time_point t0{std::chrono::seconds(100)};
  std::vector<std::size_t> writers{0, 2, 5};

  // The writers asserted in a round at t0 + ms (empty if the round was not due).
  std::vector<std::size_t> at(int ms, bool* due = nullptr) {
    std::vector<std::size_t> asserted;
    const bool d = pace.round(t0 + milliseconds(ms), writers, [&](std::size_t i) { asserted.push_back(i); });
    if (due != nullptr) *due = d;
    return asserted;
  }
};

TEST(KeepAlivePace, ARoundIsDueTenTimesPerLeaseAndAssertsEveryWriterThatWroteNothing) {
  Rounds r;
  bool due = false;
  EXPECT_EQ(r.at(0, &due), (std::vector<std::size_t>{0, 2, 5}));
  EXPECT_TRUE(due);
  EXPECT_TRUE(r.at(99, &due).empty());  // a tenth of the 1 s lease has not passed
  EXPECT_FALSE(due);
  EXPECT_EQ(r.at(100, &due), (std::vector<std::size_t>{0, 2, 5}));
  EXPECT_TRUE(due);
}

TEST(KeepAlivePace, AWriterThatWroteSinceTheRoundBeforeIsNotAssertedAndIsAgainOnceItStops) {
  Rounds r;
  r.at(0);
  r.pace.wrote(2);  // a write asserts its liveliness
  r.pace.wrote(7);  // not a manual-by-topic writer: no effect on the others
  EXPECT_EQ(r.at(100), (std::vector<std::size_t>{0, 5}));
  // Nothing written since that round: asserted again.
  EXPECT_EQ(r.at(200), (std::vector<std::size_t>{0, 2, 5}));
  // A write between two rounds that were not due still counts at the next.
  r.pace.wrote(0);
  r.at(250);
  r.pace.wrote(5);
  EXPECT_EQ(r.at(300), (std::vector<std::size_t>{2}));
}

TEST(KeepAlivePace, EveryWriterThatWritesEachRoundIsNeverAsserted) {
  Rounds r;
  for (int ms = 0; ms <= 2000; ms += 100) {
    for (const std::size_t w : r.writers) r.pace.wrote(w);
    EXPECT_TRUE(r.at(ms).empty()) << ms;
  }
}

}  // namespace
}  // namespace pheromesh::bus
