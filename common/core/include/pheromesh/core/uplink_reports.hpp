// Lockstep: a UAV's report of its UAV phase, made by its gateway from the
// UAV's state (docs/architecture.md, "Time"). The UAV writes no report of
// its own: its state of tick k says how many deposits its uplink carries in
// all its samples (UavStateMsg::tick_deposits) and whether it broadcast,
// and once the gateway holds every one of those deposits it reports the
// phase for the UAV to the conductor, with the deposits per region, as the
// UAV's own report did. One sample a UAV tick fewer, and the report cannot
// announce a deposit its gateway does not hold.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <span>

#include "pheromesh/core/messages.hpp"

namespace pheromesh::core {

class UplinkReports {
 public:
  // A state of a UAV its gateway accepted (not a finished one), and the
  // deposits that sample carried. The report of the state's tick once its
  // uplink is whole, and again for every later sample of that tick (a UAV
  // that waits re-sends its state: its report may have been lost);
  // nullopt before, and for a state older than one already seen.
  std::optional<PhaseDoneMsg> on_state(const UavStateMsg& st, std::span<const DepositMsg> carried);
  // A state its gateway refused and answered (its deposits rejected, the
  // conductor announces none of them): the UAV's report, at once.
  static PhaseDoneMsg on_refused(const UavStateMsg& st);

 private:
  struct Uplink {
    uint32_t tick = 0;
    uint32_t expected = 0;
    uint8_t broadcasts = 0;
    std::set<uint32_t> seqs;  // the deposits of the uplink held, by sequence number (a copy counts once)
    std::map<RegionId, uint32_t> per_region;
  };
  std::map<uint32_t, Uplink> uplinks_;  // UAV -> its newest uplink
};

}  // namespace pheromesh::core
