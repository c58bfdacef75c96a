// Duan 2009 over DDS: the colonies run in the UAV processes, the point
// pheromone sums in the place agents, the ETA intervals travel as broadcasts.
// A lockstep run must give the simulator's numbers (DDS domain 35).
#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers

TEST(Lockstep, DuanRunOverDdsGivesTheSimulatorsNumbers) {
  expect_lockstep_matches_sim("duan2009-small.textproto", "", 35, "lockstep-duan");
}
