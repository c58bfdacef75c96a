// core/home_watch.hpp: when a realtime UAV takes its home place agent for
// gone and moves to its backup gateway (docs/faults.md, "kill place:R").
#include <gtest/gtest.h>

#include <chrono>

#include "pheromesh/core/home_watch.hpp"

namespace pheromesh::core {
namespace home_watch_test {  // named: the unit tests build as one unity source

using namespace std::chrono_literals;
using Clock = HomeWatch::Clock;
const Clock::time_point t0 = Clock::time_point{} + 100s;

TEST(HomeWatch, SilenceIsTwoSecondsAtLeastAndTwoLeasesOrFourWithAStandby) {
  // Worked by hand: max(2000, 2 x lease) without a standby, max(2000, 4 x lease) with one.
  EXPECT_EQ(HomeWatch::silence_for(500, false), 2000ms);
  EXPECT_EQ(HomeWatch::silence_for(1000, false), 2000ms);
  EXPECT_EQ(HomeWatch::silence_for(2000, false), 4000ms);
  EXPECT_EQ(HomeWatch::silence_for(300, true), 2000ms);
  EXPECT_EQ(HomeWatch::silence_for(1000, true), 4000ms);
  EXPECT_EQ(HomeWatch::silence_for(5000, true), 20000ms);
}

TEST(HomeWatch, MovesOnceTheSilenceIsExceededAndOnlyOnce) {
  HomeWatch w(2000ms, /*has_backup=*/true);
  w.start(t0);
  EXPECT_FALSE(w.move_to_backup(t0 + 1999ms));
  EXPECT_FALSE(w.move_to_backup(t0 + 2000ms));  // exactly the silence: not yet
  EXPECT_FALSE(w.moved());
  EXPECT_TRUE(w.move_to_backup(t0 + 2001ms));
  EXPECT_TRUE(w.moved());
  EXPECT_FALSE(w.move_to_backup(t0 + 10s));  // it moved: the watch is over
  w.heard(t0 + 11s);                         // a late view from the old home does not bring it back
  EXPECT_FALSE(w.move_to_backup(t0 + 20s));
  EXPECT_TRUE(w.moved());
}

TEST(HomeWatch, AViewHeardRestartsTheSilence) {
  HomeWatch w(2000ms, true);
  w.start(t0);
  w.heard(t0 + 1500ms);
  EXPECT_FALSE(w.move_to_backup(t0 + 3000ms));  // 1.5 s after the view
  EXPECT_FALSE(w.move_to_backup(t0 + 3500ms));
  EXPECT_TRUE(w.move_to_backup(t0 + 3501ms));
  EXPECT_EQ(w.last_heard(), t0 + 1500ms);
}

TEST(HomeWatch, AViewTakenLateStillCountsForTheHomeWhenJudgedAfterTheTake) {
  // The UAV's thread was held up for 3 s; its home kept writing. The caller
  // takes the waiting views first (heard at the take), then judges.
  HomeWatch w(2000ms, true);
  w.start(t0);
  const auto resumed = t0 + 3s;
  w.heard(resumed);
  EXPECT_FALSE(w.move_to_backup(resumed));
  // Judged before the take, the same home would have been taken for gone:
  HomeWatch before(2000ms, true);
  before.start(t0);
  EXPECT_TRUE(before.move_to_backup(resumed));
}

TEST(HomeWatch, AnEarlierViewDoesNotMoveTheLastHeardBack) {
  HomeWatch w(2000ms, true);
  w.start(t0);
  w.heard(t0 + 1s);
  w.heard(t0 + 500ms);
  EXPECT_EQ(w.last_heard(), t0 + 1s);
  EXPECT_FALSE(w.move_to_backup(t0 + 3s));
  EXPECT_TRUE(w.move_to_backup(t0 + 3001ms));
}

TEST(HomeWatch, APauseRestartsTheSilence) {
  // A paused swarm sends no views: the UAV restarts the watch when it resumes.
  HomeWatch w(2000ms, true);
  w.start(t0);
  w.start(t0 + 60s);  // paused for a minute
  EXPECT_FALSE(w.move_to_backup(t0 + 61s));
  EXPECT_TRUE(w.move_to_backup(t0 + 62001ms));
}

TEST(HomeWatch, ASwarmOfOneRegionNeverMoves) {
  HomeWatch w(2000ms, /*has_backup=*/false);
  w.start(t0);
  EXPECT_FALSE(w.move_to_backup(t0 + 1h));
  EXPECT_FALSE(w.moved());
  EXPECT_EQ(w.silence(), 2000ms);
}

}  // namespace home_watch_test
}  // namespace pheromesh::core
