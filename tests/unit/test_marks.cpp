// Target marks and the revisit timer (Shao 2020 Algorithm 1, period T).
#include <gtest/gtest.h>

#include <vector>

#include "pheromesh/core/marks.hpp"

namespace pheromesh::core {
namespace {

using Kind = MarkEvent::Kind;

TEST(TargetMarks, FirstMarkOfAnUnknownTargetStartsItsTimer) {
  TargetMarks m(10);
  EXPECT_FALSE(m.marked(Cell{2, 3}));
  const auto e = m.mark(Cell{2, 3}, 5);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->kind, Kind::FirstMarked);
  EXPECT_EQ(e->cell, (Cell{2, 3}));
  EXPECT_EQ(e->tick, 5U);
  EXPECT_TRUE(m.marked(Cell{2, 3}));
  EXPECT_FALSE(m.due(Cell{2, 3}));
}

TEST(TargetMarks, MarkingATargetThatIsNotDueChangesNothing) {
  TargetMarks m(10);
  (void)m.mark(Cell{2, 3}, 5);
  EXPECT_FALSE(m.mark(Cell{2, 3}, 8).has_value());
  // The timer was not restarted by the second mark: due at 5 + 10.
  EXPECT_TRUE(m.advance(14).empty());
  EXPECT_EQ(m.advance(15).size(), 1U);
}

TEST(TargetMarks, TargetBecomesDueAfterThePeriodAndOnlyOnce) {
  TargetMarks m(10);
  (void)m.mark(Cell{1, 1}, 0);
  EXPECT_TRUE(m.advance(9).empty());
  const auto due = m.advance(10);
  ASSERT_EQ(due.size(), 1U);
  EXPECT_EQ(due[0].kind, Kind::RevisitDue);
  EXPECT_EQ(due[0].cell, (Cell{1, 1}));
  EXPECT_EQ(due[0].tick, 10U);
  EXPECT_TRUE(m.due(Cell{1, 1}));
  EXPECT_TRUE(m.marked(Cell{1, 1}));
  EXPECT_TRUE(m.advance(30).empty());  // stays due, not reported again
}

TEST(TargetMarks, RevisitOfADueTargetReportsResponseTimeAndRestartsTheTimer) {
  TargetMarks m(10);
  (void)m.mark(Cell{1, 1}, 0);
  (void)m.advance(12);  // due since tick 12
  const auto e = m.mark(Cell{1, 1}, 19);
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->kind, Kind::Revisited);
  EXPECT_EQ(e->tick, 19U);
  EXPECT_EQ(e->response_ticks, 7U);
  EXPECT_FALSE(m.due(Cell{1, 1}));
  EXPECT_TRUE(m.advance(28).empty());
  EXPECT_EQ(m.advance(29).size(), 1U);  // 19 + 10
}

TEST(TargetMarks, TargetsThatBecomeDueTogetherAreReportedByRowThenColumn) {
  TargetMarks m(5);
  const std::vector<Cell> cells{{7, 2}, {1, 9}, {3, 2}, {0, 0}, {9, 1}};
  for (const Cell c : cells) {
    (void)m.mark(c, 0);
  }
  const auto due = m.advance(5);
  ASSERT_EQ(due.size(), cells.size());
  const std::vector<Cell> expected{{0, 0}, {9, 1}, {3, 2}, {7, 2}, {1, 9}};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(due[i].cell, expected[i]) << i;
  }
}

TEST(TargetMarks, NegativeCoordinatesAreDistinctTargets) {
  TargetMarks m(5);
  (void)m.mark(Cell{-1, 2}, 0);
  EXPECT_TRUE(m.marked(Cell{-1, 2}));
  EXPECT_FALSE(m.marked(Cell{2, -1}));
  EXPECT_FALSE(m.marked(Cell{1, 2}));
}

}  // namespace
}  // namespace pheromesh::core
