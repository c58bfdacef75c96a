#include "pheromesh/core/place_intake.hpp"

#include <algorithm>
#include <iterator>
#include <string>

#include "pheromesh/core/plausibility.hpp"

namespace pheromesh::core {

namespace {
// ", and the N deposits it carried" for a refusal of a state with deposits.
std::string carried_note(std::size_t carried) {
  if (carried == 0) return {};
  return ", and the " + std::to_string(carried) + " deposit" + (carried == 1 ? "" : "s") + " it carried";
}
}  // namespace

PlaceIntake::PlaceIntake(const Setup& s) : setup_(s), state_writers_(s.state_takeover), forwarders_(s.place_takeover) {}

void PlaceIntake::heard_states(std::span<const UavStateMsg> states, Clock::time_point now) {
  for (const auto& st : states) state_writers_.heard(st.uav, st.writer, now);
}

PlaceIntake::StateCall PlaceIntake::judge_state(const UavStateMsg& st, std::size_t carried, const UavStateMsg* before,
                                                bool adopted, Cell start, double max_step, uint32_t ceiling,
                                                const IntakeRules& rules, Clock::time_point now) {
  StateCall call;
  if (st.departed || st.implausible) {
    call.verdict = IntakeVerdict::drop("a state of uav " + std::to_string(st.uav) + " that says it " +
                                       (st.departed ? "departed" : "was refused") + " (only a place agent says so)");
    call.carried = CarriedDeposits::Judge;
    return call;
  }
  const uint32_t regions = setup_.names.regions;
  const bool known = !check_uav_id(st.uav, setup_.names.uavs);
  if (known && home_region(st.uav, regions) != setup_.self) {
    // A UAV whose backup this region is: realtime, it judged its home dead
    // and came here; lockstep, only once the clock lists its home absent
    // (the shell adopted it then). Anyone else's: a stray or forged writer.
    if (backup_region(st.uav, regions) != setup_.self) {
      call.verdict = IntakeVerdict::refuse(
          Refusal::ImplausibleState, "a state of uav " + std::to_string(st.uav) + " at place agent " +
                                         std::to_string(setup_.self) + ", which is neither its home nor its backup" +
                                         carried_note(carried));
      return call;
    }
    call.adopt = !setup_.lockstep;
    adopted = adopted || call.adopt;
  } else {
    adopted = true;  // its home
  }
  // Before the motion check: a forged state must not become the UAV's last
  // accepted one.
  if (known && !state_writers_.allows(st.uav, st.writer, now)) {
    call.verdict = IntakeVerdict::refuse(Refusal::ForeignWriter,
                                         "a state of uav " + std::to_string(st.uav) +
                                             " from a writer other than the one this place agent heard it from first "
                                             "(and still hears)" +
                                             carried_note(carried));
    return call;
  }
  if (!adopted) {  // lockstep: its state counts from the tick its home is absent
    call.carried = CarriedDeposits::Judge;
    return call;
  }
  const auto judged = gate_.judge(st, before, start, max_step, ceiling, rules);
  call.carried = carried_deposits(judged);  // no deposit of a refused state goes on
  if (judged.refused_motion) {
    // The UAV flew (or says it flew) further than its policy's max_step
    // allows: refused, counted once per tick, and answered.
    if (!judged.copy) call.verdict = judged.verdict;
    call.answer = true;
    return call;
  }
  call.verdict = judged.verdict;
  call.accept = judged.verdict.taken();
  return call;
}

void PlaceIntake::accept_state(const UavStateMsg& st, Clock::time_point now) {
  state_writers_.hold(st.uav, st.writer, now);
  uav_process_[st.uav] = st.participant;
}

void PlaceIntake::departed(uint32_t uav) {
  state_writers_.release(uav);
  uav_process_.erase(uav);
}

bool PlaceIntake::from_uav_process(uint32_t uav, uint64_t participant, Clock::time_point now) const {
  if (participant == 0) return true;
  const auto it = uav_process_.find(uav);
  if (it == uav_process_.end() || it->second == 0 || it->second == participant) return true;
  return !state_writers_.held(uav, now);
}

IntakeVerdict PlaceIntake::judge_broadcast(const BroadcastMsg& b, bool up, Clock::time_point now) const {
  const std::string uav = std::to_string(b.uav);
  if (check_broadcast(b)) return IntakeVerdict::drop("a malformed broadcast of uav " + uav);
  if (check_uav_id(b.uav, setup_.names.uavs)) {
    return IntakeVerdict::refuse(Refusal::UnknownUav, "a broadcast of uav " + uav);
  }
  if (up && !from_uav_process(b.uav, b.participant, now)) {
    return IntakeVerdict::refuse(Refusal::ForeignWriter, "a broadcast of uav " + uav +
                                                             " from a process other than the one its states come from");
  }
  return IntakeVerdict::take();
}

IntakeVerdict PlaceIntake::judge_detection(const DetectionMsg& d, Clock::time_point now) const {
  return judge_uplink("a detection", d.uav, setup_.self, setup_.names, from_uav_process(d.uav, d.participant, now),
                      Refusal::ImplausibleDetection, Refusal::ForeignWriter);
}

IntakeVerdict PlaceIntake::judge_report(const PhaseDoneMsg& m, Clock::time_point now) const {
  const uint32_t uav = m.process & 0xFFFFFFU;
  return judge_uav_report(m, setup_.self, setup_.names, from_uav_process(uav, m.participant, now));
}

IntakeVerdict PlaceIntake::judge_served_chunk(const FieldMsg& f, Clock::time_point now) {
  forwarders_.heard(place_id(f.region, f.replica), f.participant, now);
  return judge_place_sample(forwarders_, f.region, f.replica, f.participant, now, setup_.names, false,
                            "a served-UAVs chunk");
}

IntakeVerdict PlaceIntake::refuse_forwarded(const DepositMsg& d, const char* why) {
  return IntakeVerdict::refuse(Refusal::ForeignWriter, "a deposit of uav " + std::to_string(d.uav) + " (seq " +
                                                           std::to_string(d.seq) +
                                                           ") forwarded by a process that is no place agent's: " + why);
}

void PlaceIntake::judge_forwarded(std::vector<DepositMsg>& taken, std::size_t first, const Forwarded& f,
                                  std::vector<IntakeVerdict>& refusals) {
  if (!setup_.lockstep) {
    judge_forwarded_realtime(taken, first, f, refusals);
    return;
  }
  // Not to the UAV's own gateway, and only of this place phase. A copy of
  // one taken before (a re-send) the desk drops.
  auto out = std::remove_if(taken.begin() + static_cast<std::ptrdiff_t>(first), taken.end(), [&](const auto& d) {
    if (f.is_copy(d)) return false;
    auto v = judge_lockstep_forward(d, f.tick, f.gateway_of(d.uav), f.refused_anyway(d));
    if (v.taken()) return false;
    refusals.push_back(std::move(v));
    return true;
  });
  taken.erase(out, taken.end());
}

void PlaceIntake::judge_forwarded_realtime(std::vector<DepositMsg>& taken, std::size_t first, const Forwarded& f,
                                           std::vector<IntakeVerdict>& refusals) {
  // A deposit refused for what it says is refused for that, whoever
  // forwarded it (the desk and the place core count it); one that would be
  // applied is judged by who forwarded it.
  const auto vouched = [&](const DepositMsg& d) { return forwarders_.vouched(d.participant) || f.refused_anyway(d); };
  const auto begin = taken.begin() + static_cast<std::ptrdiff_t>(first);
  // The common case: every forwarder known, nothing waits.
  if (parked_.empty() && std::all_of(begin, taken.end(), vouched)) return;
  std::vector<DepositMsg> ready, expired;
  if (!parked_.empty()) parked_.sweep(f.now, forwarders_.park_for(), vouched, ready, expired);
  for (const auto& d : expired) refusals.push_back(refuse_forwarded(d, "its process was never heard as a place agent"));
  std::vector<DepositMsg> forwarded(begin, taken.end());
  taken.resize(first);
  taken.insert(taken.end(), ready.begin(), ready.end());  // older first
  for (auto& d : forwarded) {
    if (vouched(d)) {
      taken.push_back(d);
    } else if (auto out = parked_.park(d, f.now)) {
      refusals.push_back(
          refuse_forwarded(*out, "too many deposits wait for their process to be heard as a place agent"));
    }
  }
  // The drain after the last tick: what still waits will not be vouched for.
  if (f.last) {
    for (const auto& d : parked_.take_all()) {
      refusals.push_back(refuse_forwarded(d, "its process was never heard as a place agent"));
    }
  }
}

std::optional<IntakeVerdict> judge_halo(const HaloMsg& h, uint32_t tick, bool lockstep, bool region_absent,
                                        uint32_t ceiling) {
  // Lockstep: a ring of an earlier tick is a late re-send (no news); one of a
  // later tick cannot exist while this place agent has not reported this
  // tick's phase done, so the conductor has not begun the next.
  if (lockstep && (h.tick < tick || region_absent)) return std::nullopt;
  if (lockstep && h.tick > tick) {
    return IntakeVerdict::refuse(Refusal::TickFarAhead, "a halo ring of region " + std::to_string(h.region) +
                                                            " for tick " + std::to_string(h.tick) +
                                                            " in the place phase of tick " + std::to_string(tick));
  }
  if (auto reason = check_tick_reachable(h.tick, ceiling, "halo")) {
    return IntakeVerdict::refuse(Refusal::TickFarAhead, *reason);
  }
  return IntakeVerdict::take();
}

}  // namespace pheromesh::core
