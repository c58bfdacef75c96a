// Who may send what (issue 42 D4-D5, docs/architecture.md "Who wrote it"):
// the judgements a receiver makes of a sample by the name it carries and the
// process that wrote it, beyond what the sample says (intake.hpp) and beyond
// the latches themselves (writer_latch.hpp, place_vouch.hpp).
//
// - Only names that exist: a place agent is (region, replica) of the run
//   that runs - a region of its map, replica 0 or, in a swarm with hot
//   standbys, 1. A health, a served-UAVs chunk or a place agent's report
//   under any other id is refused (Refusal::UnknownPlace), so that it
//   neither latches an id that makes its process a place agent for every
//   relay nor puts counters of its own into metrics.json.
// - Only from their holder: a health or a served-UAVs chunk only from the
//   process that holds its place id (or takes it now); a lockstep report
//   (PhaseDone) of a place agent only from the process that holds its id,
//   and a UAV's only from a process that holds a replica of the UAV's home
//   or backup region - the gateways that relay it (Refusal::ForeignReport).
//   A gateway relays a UAV's report only if it can be the UAV's gateway and
//   the report came from the UAV's own process.
// - Lockstep forwarded deposits: only of the place phase under way, and
//   never of a UAV whose gateway the receiver is (its states carry those).
//
// Time, where needed, is passed in. Pure, no I/O.
#pragma once

#include <chrono>
#include <cstdint>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/intake.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/place_vouch.hpp"

namespace pheromesh::core {

// The names of the swarm that runs.
struct SwarmNames {
  uint32_t uavs = 0;      // UAV ids 0..uavs-1
  uint32_t regions = 0;   // region ids 0..regions-1
  uint32_t replicas = 1;  // replica ids 0..replicas-1 per region (replicas_of)
};
// Place agents per region: the primary, and one hot standby in a swarm
// with standbys (pheromesh run --standby).
inline constexpr uint32_t replicas_of(bool standby) { return standby ? 2U : 1U; }

// A (region, replica) the run has.
IntakeVerdict check_place_id(RegionId region, uint32_t replica, const SwarmNames& names, const char* what);

// What only place agent (region, replica) writes - `what`: its health, its
// served-UAVs chunk - from `participant`, which `places` has heard already
// (PlaceVouch::heard, for every sample of a take first). Refused if the run
// has no such place agent (UnknownPlace) or another process holds its id
// (ForeignWriter); taken, it latches the id to `participant` (PlaceVouch::
// claim; `new_life`: of a later life of the place agent).
IntakeVerdict judge_place_sample(PlaceVouch& places, RegionId region, uint16_t replica, uint64_t participant,
                                 PlaceVouch::Clock::time_point now, const SwarmNames& names, bool new_life,
                                 const char* what);

// The conductor's side: a lockstep report (PhaseDone) as the ground station
// took it, written by `m.participant`. A place agent's from the process that
// holds its place id (or nobody yet: its Ready may come before its health);
// a UAV's from a process that holds a replica of its home or backup region
// (or none of them is held yet).
IntakeVerdict judge_report(const PhaseDoneMsg& m, const PlaceVouch& places, const SwarmNames& names);

// What a UAV sends up through its gateway (`what`: "a detection", "a
// lockstep report"), at place agent `self` before it relays it: of a UAV of
// the swarm (UnknownUav), whose home or backup `self` is (else
// `not_gateway`), written by the UAV's own process (`from_uav_process`: the
// process whose writer holds the UAV's states, or no live holder yet; else
// `foreign`).
IntakeVerdict judge_uplink(const char* what, uint32_t uav, RegionId self, const SwarmNames& names,
                           bool from_uav_process, Refusal not_gateway, Refusal foreign);
// A UAV's report (PhaseDone) at its gateway: judge_uplink with ForeignReport
// for both; a report that is not a UAV's is dropped.
IntakeVerdict judge_uav_report(const PhaseDoneMsg& m, RegionId self, const SwarmNames& names, bool from_uav_process);

// A lockstep place agent in the place phase of `place_tick` takes a deposit
// another place agent forwarded (not a copy of one it took before: a
// re-send, or the standby's forward of the same deposit, which the desk
// drops). Refused if this place agent is the UAV's gateway
// (`gateway_of_uav`: it takes that UAV's deposits from its states; no honest
// forward crosses a lockstep gateway) - ForeignWriter - or if it is not of
// this tick: the conductor announced this place phase's deposits from what
// the UAVs reported, and a deposit of another tick is none of them; applied
// at this tick, a late one would land a tick late (UnannouncedDeposit). One
// the place core refuses anyway for what it says (`refused_anyway`:
// malformed, a UAV outside the swarm, a sequence number it cannot have
// reached) is left to it, and counted for that.
IntakeVerdict judge_lockstep_forward(const DepositMsg& d, uint32_t place_tick, bool gateway_of_uav,
                                     bool refused_anyway);

}  // namespace pheromesh::core
