// The Shostak GPS-denied stigmergy policy over DDS: a lockstep run of the
// small Shostak scenario (3 UAVs, 2 x 2 place agents, a target found and
// broadcast within the run) gives the simulator's numbers. DDS domain 33.
#include "harness.hpp"

using namespace pheromesh::itest;  // NOLINT: the test helpers

TEST(Lockstep, ShostakRunOverDdsGivesTheSimulatorsNumbers) {
  expect_lockstep_matches_sim("shostak-small.textproto", "", 33, "lockstep-shostak");
}
