// The checks a received view or field chunk passes before a shell hands it
// to the core, the same in every process (docs/architecture.md, "What a
// receiver refuses"). Each returns a verdict: take it, drop it as malformed
// (counted as rejected), or refuse it as implausible (counted by reason,
// core/plausibility.hpp). Pure functions, no I/O.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/plausibility.hpp"

namespace pheromesh::core {

struct IntakeVerdict {
  enum class Kind : uint8_t { Take, Drop, Refuse };
  Kind kind = Kind::Take;
  Refusal refusal = Refusal::UnknownUav;  // Refuse only
  std::string reason;                     // Drop and Refuse

  static IntakeVerdict take() { return {}; }
  static IntakeVerdict drop(std::string why) { return {Kind::Drop, Refusal::UnknownUav, std::move(why)}; }
  static IntakeVerdict refuse(Refusal r, std::string why) { return {Kind::Refuse, r, std::move(why)}; }
  [[nodiscard]] bool taken() const { return kind == Kind::Take; }
};

// What the receiver knows of the swarm that runs.
struct IntakeRules {
  const MapGeometry& geo;
  int layers = 0;
  std::span<const ValueRange> ranges;  // per layer
  uint32_t swarm = 0;                  // UAVs
};

// A view as a whole, for UAV `me`: addressed to it, of a tick the sender can
// have reached (`ceiling`), no tile value outside its layer's range. The
// tiles and states inside are checked one by one (check_view_tile,
// check_neighbour): a bad one drops only itself.
IntakeVerdict check_view(const ViewMsg& v, uint32_t me, uint32_t ceiling, const IntakeRules& r);
IntakeVerdict check_view_tile(const TileMsg& t, const IntakeRules& r);
IntakeVerdict check_neighbour(const UavStateMsg& s, const IntakeRules& r);
// Another UAV's broadcast: well formed, from a UAV of the swarm.
IntakeVerdict check_broadcast_from(const BroadcastMsg& b, const IntakeRules& r);
// A home UAV's state at its place agent: a UAV of the swarm, well formed, of
// a reachable tick, and no further from its last accepted state `before`
// (nullptr: none yet; then from its start cell) than it can fly in the ticks
// between. The place agent cannot tell a restarted UAV from a forger: a state
// whose tick went back may start again from the start cell.
IntakeVerdict check_home_state(const UavStateMsg& s, const UavStateMsg* before, Cell start, double max_step,
                               uint32_t ceiling, const IntakeRules& r);
// A UAV's gateway judging the UAV's states: the one plausibility rule of
// the simulator and the place agents (docs/architecture.md "Plausibility").
// check_home_state decides; this remembers the tick of each UAV's latest
// refused state, so that a copy of it (a lockstep re-send, a second uplink
// sample of a tick with many deposits, the closing state of the same tick)
// is answered again but counted once. A refused state is an answer, not a
// silence: its gateway tells the ground station (refused_answer) and gives
// the UAV an empty view of its tick, so no lockstep phase waits for it.
// The caller keeps the last accepted state (`before`). A taken state whose
// tick is before `before`'s (a restarted UAV) clears the UAV's refusals.
class StateGate {
 public:
  struct Judged {
    IntakeVerdict verdict;
    // A refusal of the motion rule (Refusal::ImplausibleState): an answer.
    bool refused_motion = false;
    // ... of a tick refused before: not counted again.
    bool copy = false;
  };
  Judged judge(const UavStateMsg& s, const UavStateMsg* before, Cell start, double max_step, uint32_t ceiling,
               const IntakeRules& r);
  // The tick of the UAV's latest refused state, if any.
  [[nodiscard]] std::optional<uint32_t> refused_tick(uint32_t uav) const;

 private:
  std::map<uint32_t, uint32_t> refused_tick_;
};

// What becomes of the deposits a judged state carries (issue 42 D4): a
// gateway forwards no deposit of a state it refused.
// - Judge: the state was taken, or dropped as malformed (a policy that
//   reports a position off the map): they go on as any deposit, applied
//   here or forwarded to their owners, and judged there.
// - Reject: the state was refused for its motion - the UAV's own deposits,
//   counted in its deposits_sent. Neither applied nor forwarded: its gateway
//   takes them (they are confirmed to the UAV), counts them received and
//   rejected ("carried by a state its gateway refused") and refused
//   (Refusal::RefusedStateDeposit), so sent == applied + rejected holds; the
//   conductor announces none of them to any region and the simulator does
//   the same.
// - Refuse: the state was refused for what it names - a UAV outside the
//   swarm, a tick the run cannot have reached: no UAV's. Its deposits are
//   refused with it (RefusedStateDeposit, one per deposit) and reach no
//   ledger.
enum class CarriedDeposits : uint8_t { Judge, Reject, Refuse };
CarriedDeposits carried_deposits(const StateGate::Judged& j);
inline constexpr const char* kRejectedWithState = "carried by a state its gateway refused";

// What the gateway relays to the ground station for a refused state `s`:
// `s` marked UavStateMsg::implausible, without its uplink.
UavStateMsg refused_answer(const UavStateMsg& s);

// A field chunk of another region, as a whole: well formed (its region, every
// tile and state), of a reachable tick, values in range, UAVs of the swarm.
IntakeVerdict check_field_chunk(const FieldMsg& f, uint32_t ceiling, const IntakeRules& r);

}  // namespace pheromesh::core
