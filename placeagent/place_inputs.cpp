// A place agent's inputs of a tick: its home UAVs' states (and the deposits
// they carry), the deposits other place agents forwarded, routed to this
// region's inbox or forwarded to their owners. What to do with each sample
// is core::PlaceIntake's judgement; this file takes the samples from the bus
// and does it. In lockstep every input is waited for exactly as the clock
// announced it; in realtime the latest received is used.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "place_app.hpp"

namespace pheromesh::placeagent {

void PlaceApp::take_deposits() {
  // The deposits its UAVs' states carried (take_home_states), then those
  // other place agents forwarded.
  taken_.swap(uplinked_);
  uplinked_.clear();
  const std::size_t carried = taken_.size();
  bus_->take_deposits(taken_);
  judge_forwarded(carried);
  reject_carried();
  for (const auto& d : taken_) {
    const auto route = desk_.take(d, current_tick_);
    log_->debug("took deposit uav {} seq {} tick {} region {}: {}", d.uav, d.seq, d.tick, d.region,
                static_cast<int>(route));
    switch (route) {
      case core::DepositRoute::Apply:
        inbox_.push_back(d);
        break;
      case core::DepositRoute::Forward:
        forward(d);
        break;
      case core::DepositRoute::Copy:
        break;
    }
  }
  flush_forwards();
}

void PlaceApp::judge_forwarded(std::size_t first) {
  core::PlaceIntake::Forwarded f;
  f.tick = current_tick_;
  f.now = std::chrono::steady_clock::now();
  f.last = last_tick_;
  f.refused_anyway = [&](const core::DepositMsg& d) { return core_.refuses_outright(d, current_tick_); };
  f.is_copy = [&](const core::DepositMsg& d) { return desk_.is_copy(d); };
  f.gateway_of = [&](uint32_t uav) {
    return std::find(gateway_uavs_.begin(), gateway_uavs_.end(), uav) != gateway_uavs_.end();
  };
  verdicts_.clear();
  intake_.judge_forwarded(taken_, first, f, verdicts_);
  for (const auto& v : verdicts_) (void)audit_.admit(v);
}

void PlaceApp::forward(const core::DepositMsg& d) {
  // A home UAV's deposit for another region: to the owner's place agent,
  // with the others of this take for that region (flush_forwards).
  if (is_absent(d.region)) {
    ++deposits_lost_;  // the conductor counts it lost (deposits_lost)
  } else if (bus_->matched_deposit_readers(d.region) == 0) {
    forward_failed(d, "its place agent was not reachable");
  } else {
    to_forward_[d.region].push_back(d);
  }
}

void PlaceApp::flush_forwards() {
  // One sample per owner and take (core::deposit_batches), not one per
  // deposit: each sample costs its own DATA, HEARTBEAT and ACKNACK.
  for (auto& [owner, deposits] : to_forward_) {
    for (const auto& batch : core::deposit_batches(cfg_.region, current_tick_, deposits)) {
      if (resend_.deposits(batch, owner)) {
        deposits_forwarded_ += batch.deposits.size();
      } else {
        for (const auto& d : batch.deposits) forward_failed(d, "writing it failed");
      }
    }
    deposits.clear();
  }
}

void PlaceApp::forward_failed(const core::DepositMsg& d, const char* why) {
  // Not a receipt: only the region a deposit is for counts it (received,
  // applied or rejected), so that each deposit counts once however many
  // replicas of its UAV's home forward it. When none got it through, it is
  // in the run's deposits_lost (sent, received by no place agent). Counted
  // as received and rejected here, a standby's failed forwards of deposits
  // its primary got through counted twice (received 3332 of 3310 sent).
  if (forwards_failed_++ < 3) {
    log_->warn(
        "a deposit of uav {} for region {} was not forwarded: {} (counted lost unless another replica of "
        "this region forwarded it)",
        d.uav, d.region, why);
  }
}

void PlaceApp::take_home_states(uint32_t tick, bool batch) {
  state_inbox_.clear();
  bus_->take_uav_states(state_inbox_);
  const uint32_t ceiling = tick_ceiling();
  const auto now = std::chrono::steady_clock::now();
  intake_.heard_states(state_inbox_, now);
  for (auto& st : state_inbox_) {
    // The deposits a state carries wait for take_deposits, which routes them
    // as if each had come alone, unless the state was refused: those go with
    // it (core::carried_deposits; a forger cannot send deposits in a UAV's
    // name). The state goes on without them: into views and to the ground
    // station.
    carried_.clear();
    carried_.swap(st.deposits);
    const core::UavStateMsg* before = views_.state(st.uav);
    const auto call =
        intake_.judge_state(st, carried_.size(), before, adopted_.contains(st.uav),
                            core::uav_start(scenario_, traits_, st.uav), traits_.max_step, ceiling, rules_, now);
    if (call.adopt) adopt(st.uav, nullptr);
    // Lockstep: the UAV's report of its phase, made here from its state
    // (core::UplinkReports) once every deposit of its uplink is here.
    const bool report = cfg_.common.lockstep() && !st.finished;
    std::optional<core::PhaseDoneMsg> done;
    if (report && call.accept) done = uplink_reports_.on_state(st, carried_);
    if (report && call.answer) done = core::UplinkReports::on_refused(st);
    st.tick_deposits = 0;  // the gateway's to use: nested or relayed, a state carries none
    st.broadcasts = 0;
    if (call.carried) route_carried(*call.carried);
    const bool taken = audit_.admit(call.verdict);
    if (call.answer) answer_refused(st);
    if (done) {
      relay_batch_.add_report(st.uav, done->tick, now);
      reports_out_.push_back(std::move(*done));
    }
    if (!taken || !call.accept) continue;
    intake_.accept_state(st, now);
    if (before == nullptr || st.tick > before->tick) heard_at_[st.uav] = tick;
    views_.update_state(st);
    // The ground station hears the UAVs through their gateways (relays),
    // all those of a batch in one sample (below).
    relayed_.push_back(st);
    ++states_relayed_;
  }
  take_departures();
  // The reports with the states, in one sample: the conductor's UAV phase
  // is complete when the last report is here, and it has the states by then.
  // Lockstep, between phases: one sample per UAV phase, not per state
  // (core::RelayBatch); realtime and the place phase: those of this take.
  if (batch && cfg_.common.lockstep() && !relay_batch_.due(gateway_uavs_, now)) return;
  if (!relayed_.empty() || !reports_out_.empty()) {
    bus_->relay_states(relayed_, cfg_.region, cfg_.replica, tick, reports_out_);
  }
  reports_relayed_ += reports_out_.size();
  reports_out_.clear();
  relayed_.clear();
  relay_batch_.sent();
}

void PlaceApp::take_departures() {
  departed_.clear();
  bus_->take_departed_uavs(departed_);
  for (const auto& d : departed_) {
    const uint32_t u = d.uav;
    intake_.departed(u);  // every state writer of u vanished: the next one heard is u
    if (std::find(gateway_uavs_.begin(), gateway_uavs_.end(), u) == gateway_uavs_.end()) continue;
    core::UavStateMsg gone;
    gone.uav = u;
    if (const core::UavStateMsg* last = views_.state(u)) gone = *last;
    gone.departed = true;
    relayed_.push_back(gone);
    relay_batch_.add_departure();
    log_->info(
        "uav {} departed (its state writer's liveliness lapsed: it died, hangs or its packets were lost); told "
        "the ground station",
        u);
  }
}

void PlaceApp::answer_refused(const core::UavStateMsg& st) {
  relayed_.push_back(core::refused_answer(st));
  if (std::find(refused_views_.begin(), refused_views_.end(), st.uav) == refused_views_.end()) {
    refused_views_.push_back(st.uav);
  }
}

void PlaceApp::route_carried(core::CarriedDeposits fate) {
  switch (fate) {
    case core::CarriedDeposits::Judge:
      uplinked_.insert(uplinked_.end(), carried_.begin(), carried_.end());
      break;
    case core::CarriedDeposits::Reject:
      refused_carried_.insert(refused_carried_.end(), carried_.begin(), carried_.end());
      break;
    case core::CarriedDeposits::Refuse:
      audit_.refuse(core::Refusal::RefusedStateDeposit,
                    fmt::format("{} deposit(s) carried by a state of no UAV of the swarm", carried_.size()),
                    carried_.size());
      break;
  }
}

void PlaceApp::reject_carried() {
  // Taken (the UAV's view confirms them; lockstep: they count among the
  // deposits its state says it sent) but neither applied nor forwarded; a
  // copy (a re-sent state) once.
  rejected_carried_.clear();
  for (const auto& d : refused_carried_) {
    if (desk_.take(d, current_tick_) != core::DepositRoute::Copy) rejected_carried_.push_back(d);
  }
  refused_carried_.clear();
  core_.reject(rejected_carried_, core::kRejectedWithState);
  audit_.refuse(core::Refusal::RefusedStateDeposit,
                fmt::format("{} deposit(s) carried by a state its gateway refused", rejected_carried_.size()),
                rejected_carried_.size());
}

uint32_t PlaceApp::home_states_of(uint32_t tick) const {
  // A refused state is an answer too (core::StateGate).
  return static_cast<uint32_t>(std::count_if(gateway_uavs_.begin(), gateway_uavs_.end(), [&](uint32_t u) {
    const core::UavStateMsg* st = views_.state(u);
    const auto refused = intake_.refused_tick(u);
    return (st != nullptr && st->tick >= tick) || (refused && *refused >= tick);
  }));
}

bool PlaceApp::holds_home_deposits(uint32_t tick) const {
  // A home UAV's state of this tick counts every deposit it wrote so far;
  // those for other regions must be forwarded in this phase too, or their
  // owners wait for them while this place agent waits for their fields.
  return std::all_of(gateway_uavs_.begin(), gateway_uavs_.end(), [&](uint32_t u) {
    const core::UavStateMsg* st = views_.state(u);
    if (st == nullptr || st->tick < tick) return true;
    // An adopted UAV: the deposits it sent since it came here.
    auto a = adopted_.find(u);
    const auto [sent_before, taken_before] = a == adopted_.end() ? std::pair<uint64_t, uint64_t>{0, 0} : a->second;
    return desk_.taken_from(u) - taken_before >= st->deposits_sent - std::min(sent_before, st->deposits_sent);
  });
}

uint32_t PlaceApp::deposits_of(uint32_t tick) const {
  return static_cast<uint32_t>(std::count_if(inbox_.begin(), inbox_.end(),
                                             [&](const auto& d) { return d.tick == tick && !core_.refuses(d, tick); }));
}

bool PlaceApp::inputs_held(uint32_t tick) const {
  // Lockstep: exactly the deposits the UAVs reported for this region and the
  // states of the home UAVs that took part in the UAV phase, as the clock
  // announced, and every deposit those home UAVs wrote (some to forward,
  // holds_home_deposits). Waiting for these exact samples replaces the UAVs' wait for
  // acknowledgements. Forged deposits carrying this tick must not stand in
  // for real ones (the place would apply the tick before all of them arrived).
  // Meanwhile the deposits forwarded so far go out again after a quiet spell
  // (the lockstep loop's re-sender): two place agents each waiting for the
  // other's lost forward would otherwise wait for each other.
  return !demand_ || (deposits_of(tick) >= demand_->deposits && home_states_of(tick) >= demand_->states &&
                      holds_home_deposits(tick));
}

void PlaceApp::log_inputs_late(uint32_t tick) const {
  log_->error("tick {}: {} of {} announced deposits and {} of {} home UAV states arrived{}; applying those", tick,
              deposits_of(tick), demand_->deposits, home_states_of(tick), demand_->states,
              holds_home_deposits(tick) ? "" : ", not every deposit of the home UAVs to forward");
}

}  // namespace pheromesh::placeagent
