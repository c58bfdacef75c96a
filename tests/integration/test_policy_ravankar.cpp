// Ravankar 2016 policy over DDS: a lockstep run of the small scenario (ellipse
// deposits that span the 2 x 2 regions, followers reading across borders)
// gives the simulator's numbers. DDS domain 34.
#include "harness.hpp"

namespace {

using namespace pheromesh::itest;

TEST(Lockstep, RavankarRunOverDdsGivesTheSimulatorsNumbers) {
  expect_lockstep_matches_sim("ravankar2016-small.textproto", "", 34, "lockstep-ravankar");
}

}  // namespace
