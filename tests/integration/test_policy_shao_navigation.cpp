// Shao 2020 navigation (Shao 2020 Sec. 5) over DDS: lockstep equals the simulator, on a
// reduced navigation scenario where the leader arrives and the search takes over.
#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers

TEST(Lockstep, ShaoNavigationRunOverDdsGivesTheSimulatorsNumbers) {
  expect_lockstep_matches_sim("small-navigation.textproto", "", 31, "lockstep-navigation");
  // The run is not trivial: the leader handed over to the search.
  const auto m = read_metrics(out_path("lockstep-navigation-sim"));
  EXPECT_FALSE(m["leader_arrival_tick"].is_null()) << m.dump(2);
}
