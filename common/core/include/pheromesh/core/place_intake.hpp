// The place agent's judgement of what it receives (issue 43 D1,
// docs/architecture.md "What a receiver refuses"): its home UAVs' states and
// the writers they come from, the deposits other place agents forward, the
// detections, broadcasts and reports its UAVs send up, the other place
// agents' served-UAVs chunks and its neighbours' halo rings. The shell takes
// the samples from the bus, asks this component what to do with each and
// does it (counts the verdicts in its SampleAudit, relays, applies); the
// simulator needs none of it (no writers, no forwards). Time is passed in.
// Pure, no I/O.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/intake.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/place_vouch.hpp"
#include "pheromesh/core/sender_judge.hpp"
#include "pheromesh/core/writer_latch.hpp"

namespace pheromesh::core {

class PlaceIntake {
 public:
  using Clock = std::chrono::steady_clock;

  struct Setup {
    RegionId self = 0;
    SwarmNames names;
    bool lockstep = false;
    // A UAV's state writer silent this long gives the UAV up (WriterLatch).
    Clock::duration state_takeover{};
    // A place agent's process silent this long gives its id up (PlaceVouch).
    Clock::duration place_takeover{};
  };
  explicit PlaceIntake(const Setup& s);

  // ---- Home states -------------------------------------------------------
  // What to do with one state of a take, judged by judge_state.
  struct StateCall {
    // Counted (SampleAudit::admit) after `carried` was routed; take() when
    // there is nothing to count.
    IntakeVerdict verdict;
    // Where the deposits the state carried go; nullopt: they go with the
    // state's refusal (counted in it, reach no ledger).
    std::optional<CarriedDeposits> carried;
    bool adopt = false;   // realtime: this place agent is the UAV's backup and adopts it first
    bool answer = false;  // refused for its motion: answered (refused_answer, an empty view)
    bool accept = false;  // the UAV's last accepted state now (accept_state)
  };
  // Every state of a take, before any is judged: a holder heard is not
  // silent, however long this place agent stalled (WriterLatch::heard).
  void heard_states(std::span<const UavStateMsg> states, Clock::time_point now);
  // One state (its deposits taken out already: `carried` of them). `before`:
  // the UAV's last accepted state (nullptr: none); `adopted`: this place
  // agent adopted the UAV as its backup gateway (lockstep: the clock listed
  // its home absent). Only a state of a UAV whose home or backup this region
  // is, from the writer latched for it, goes to the state gate (the one
  // plausibility rule, StateGate).
  StateCall judge_state(const UavStateMsg& st, std::size_t carried, const UavStateMsg* before, bool adopted, Cell start,
                        double max_step, uint32_t ceiling, const IntakeRules& rules, Clock::time_point now);
  // A state judge_state accepted: its writer holds the UAV, its process is
  // the UAV's (from_uav_process).
  void accept_state(const UavStateMsg& st, Clock::time_point now);
  // Every state writer of `uav` vanished: the next one heard is the UAV.
  void departed(uint32_t uav);
  // The tick of the UAV's latest refused state (StateGate::refused_tick).
  [[nodiscard]] std::optional<uint32_t> refused_tick(uint32_t uav) const { return gate_.refused_tick(uav); }
  // `participant` is the process whose writer holds `uav`'s states, or this
  // place agent cannot tell (0, no process latched, or its holder silent).
  [[nodiscard]] bool from_uav_process(uint32_t uav, uint64_t participant, Clock::time_point now) const;

  // ---- What the UAVs send up, what comes down -----------------------------
  // A broadcast: well formed (else dropped), of a UAV of the swarm
  // (UnknownUav); going up (`up`), from the UAV's own process (ForeignWriter).
  [[nodiscard]] IntakeVerdict judge_broadcast(const BroadcastMsg& b, bool up, Clock::time_point now) const;
  // A detection going up (core::judge_uplink).
  [[nodiscard]] IntakeVerdict judge_detection(const DetectionMsg& d, Clock::time_point now) const;
  // A UAV's lockstep report going up (core::judge_uav_report).
  [[nodiscard]] IntakeVerdict judge_report(const PhaseDoneMsg& m, Clock::time_point now) const;

  // ---- Other place agents --------------------------------------------------
  // A served-UAVs chunk of another place agent, its checks passed: judged by
  // who wrote it (judge_place_sample); it vouches for its process as a
  // forwarder of deposits.
  IntakeVerdict judge_served_chunk(const FieldMsg& f, Clock::time_point now);

  // The deposits other place agents forwarded, in `taken` from index
  // `first`, judged where they stand: those not taken are removed (and
  // realtime, may come back from the parking at a later call) and their
  // refusals appended to `refusals` (SampleAudit::admit each).
  // - lockstep: core::judge_lockstep_forward, a copy the desk drops left to it;
  // - realtime: a deposit refused anyway for what it says, or forwarded by a
  //   vouched process, is taken; the others wait (Parked) for their process
  //   to be vouched for, and are refused (ForeignWriter) after
  //   PlaceVouch::park_for(), when the parking overflows, or (`last`) at the
  //   drain after the last tick. Those parked before come first.
  struct Forwarded {
    uint32_t tick = 0;  // the place tick under way
    Clock::time_point now{};
    bool last = false;  // realtime: the drain after the last tick
    // Refused anyway for what it says (malformed, a UAV outside the swarm, a
    // sequence number it cannot have reached): left to the place core.
    std::function<bool(const DepositMsg&)> refused_anyway;
    // Lockstep: a copy of a deposit taken before (DepositDesk::is_copy).
    std::function<bool(const DepositMsg&)> is_copy;
    // Lockstep: this place agent is the gateway of the UAV.
    std::function<bool(uint32_t uav)> gateway_of;
  };
  void judge_forwarded(std::vector<DepositMsg>& taken, std::size_t first, const Forwarded& f,
                       std::vector<IntakeVerdict>& refusals);

 private:
  static IntakeVerdict refuse_forwarded(const DepositMsg& d, const char* why);
  void judge_forwarded_realtime(std::vector<DepositMsg>& taken, std::size_t first, const Forwarded& f,
                                std::vector<IntakeVerdict>& refusals);

  Setup setup_;
  // Each UAV's state writer, as first heard (issue 28).
  WriterLatch state_writers_;
  StateGate gate_;
  std::unordered_map<uint32_t, uint64_t> uav_process_;  // UAV -> the process of its latched state writer
  PlaceVouch forwarders_;                               // realtime: other place agents' processes
  Parked<DepositMsg> parked_;
};

// A neighbour's halo ring at place tick `tick`, before its contents are
// checked (PlaceCore::accept_halo). nullopt: ignored without a word
// (lockstep: a late re-send of an earlier tick, or of a region the clock
// lists absent); otherwise take() or a refusal (TickFarAhead: lockstep, of a
// later tick, which cannot exist before this place agent reported this
// tick's phase done; a tick the run cannot have reached, `ceiling`).
std::optional<IntakeVerdict> judge_halo(const HaloMsg& h, uint32_t tick, bool lockstep, bool region_absent,
                                        uint32_t ceiling);

}  // namespace pheromesh::core
