// Liu 2022 (ESUSTPM) over DDS: the lockstep run of the processes gives the
// simulator's numbers (metrics, UAV end positions, the TPM field summary and
// the final field).
#include "harness.hpp"

using namespace pheromesh::itest;

TEST(Lockstep, LiuRunOverDdsGivesTheSimulatorsNumbers) {
  expect_lockstep_matches_sim("liu2022-small.textproto", "", 32, "lockstep-liu");
}
