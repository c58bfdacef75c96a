// One tick of a place agent: its inputs (deposits, forwarded to their
// owners or applied here, and its home UAVs' states), the exchange of border
// rings with its neighbours, and its field and its home UAVs' views. In
// lockstep every input is waited for exactly as the clock announced it;
// in realtime the latest received is used.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <set>

#include "pheromesh/runtime/await.hpp"
#include "place_app.hpp"

namespace pheromesh::placeagent {

namespace {
using Clock = std::chrono::steady_clock;
// Realtime: a home UAV not heard for this many place ticks gets no more
// views (it died or finished); in lockstep every view is sent.
constexpr uint32_t kViewsAfterSilence = 20;
// Realtime: neighbour states at most this many ticks older than the UAV's
// own go into its view (UavCore keeps the same window).
constexpr uint32_t kNeighbourAge = 4;
}  // namespace

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
}

void PlaceApp::judge_forwarded(std::size_t first) {
  if (cfg_.common.lockstep()) {
    // core::judge_lockstep_forward: not to the UAV's own gateway, and only
    // of this place phase. A copy of one taken before (a re-send) the desk drops.
    auto out = std::remove_if(taken_.begin() + static_cast<std::ptrdiff_t>(first), taken_.end(), [&](const auto& d) {
      const bool gateway = std::find(gateway_uavs_.begin(), gateway_uavs_.end(), d.uav) != gateway_uavs_.end();
      const bool says =
          core::check_deposit(d, geo_, cfg_.region, core_.layer_count()) || core_.refuses(d, current_tick_);
      return !desk_.is_copy(d) && !audit_.admit(core::judge_lockstep_forward(d, current_tick_, gateway, says));
    });
    taken_.erase(out, taken_.end());
    return;
  }
  // A deposit refused for what it says (malformed, a UAV outside the swarm,
  // a sequence number it cannot have reached) is refused for that, whoever
  // forwarded it (the desk and the place core count it); one that would be
  // applied is judged by who forwarded it.
  const auto vouched = [&](const core::DepositMsg& d) {
    return forwarders_.vouched(d.participant) || core::check_deposit(d, geo_, cfg_.region, core_.layer_count()) ||
           core_.refuses(d, current_tick_);
  };
  // The common case: every forwarder known, nothing waits.
  if (parked_deposits_.empty() &&
      std::all_of(taken_.begin() + static_cast<std::ptrdiff_t>(first), taken_.end(), vouched)) {
    return;
  }
  const auto now = Clock::now();
  std::vector<core::DepositMsg> ready, expired;
  if (!parked_deposits_.empty()) parked_deposits_.sweep(now, forwarders_.park_for(), vouched, ready, expired);
  for (const auto& d : expired) refuse_forwarded(d, "its process was never heard as a place agent");
  std::vector<core::DepositMsg> forwarded(taken_.begin() + static_cast<std::ptrdiff_t>(first), taken_.end());
  taken_.resize(first);
  taken_.insert(taken_.end(), ready.begin(), ready.end());  // older first
  for (auto& d : forwarded) {
    if (vouched(d)) {
      taken_.push_back(d);
    } else if (auto out = parked_deposits_.park(d, now)) {
      refuse_forwarded(*out, "too many deposits wait for their process to be heard as a place agent");
    }
  }
  // The drain after the last tick: what still waits will not be vouched for.
  if (last_tick_) {
    for (const auto& d : parked_deposits_.take_all())
      refuse_forwarded(d, "its process was never heard as a place agent");
  }
}

void PlaceApp::refuse_forwarded(const core::DepositMsg& d, const char* why) {
  audit_.refuse(core::Refusal::ForeignWriter,
                fmt::format("a deposit of uav {} (seq {}) forwarded by a process that is no place agent's: {}", d.uav,
                            d.seq, why));
}

bool PlaceApp::from_uav_process(uint32_t uav, uint64_t participant, Clock::time_point now) const {
  if (participant == 0) return true;
  const auto it = uav_process_.find(uav);
  if (it == uav_process_.end() || it->second == 0 || it->second == participant) return true;
  return !state_writers_.held(uav, now);
}

void PlaceApp::forward(const core::DepositMsg& d) {
  // A home UAV's deposit for another region: to the owner's place agent.
  if (is_absent(d.region)) {
    ++deposits_lost_;  // the conductor counts it lost (deposits_lost)
  } else if (bus_->matched_deposit_readers(d.region) == 0) {
    forward_failed(d, "its place agent was not reachable");
  } else if (resend_.deposit(d, d.region)) {
    ++deposits_forwarded_;
  } else {
    forward_failed(d, "writing it failed");
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

void PlaceApp::take_home_states(uint32_t tick) {
  state_inbox_.clear();
  bus_->take_uav_states(state_inbox_);
  const uint32_t ceiling = tick_ceiling();
  const auto now = std::chrono::steady_clock::now();
  relayed_.clear();
  // Whose writer wrote in this take: a holder heard here is not silent,
  // however long this place agent was stalled (WriterLatch::heard).
  for (const auto& st : state_inbox_) state_writers_.heard(st.uav, st.writer, now);
  for (auto& st : state_inbox_) {
    // The deposits a state carries wait for take_deposits, which routes them
    // as if each had come alone (their own checks are core::DepositDesk's
    // and the place core's), unless the state came from a writer that is not
    // its UAV's or is refused: those go with it (core::carried_deposits; a
    // forger cannot send deposits in a UAV's name). The state goes on
    // without them: into views and to the ground station.
    carried_.clear();
    carried_.swap(st.deposits);
    if (st.departed || st.implausible) {
      audit_.drop(fmt::format("a state of uav {} that says it {} (only a place agent says so)", st.uav,
                              st.departed ? "departed" : "was refused"));
      route_carried(core::CarriedDeposits::Judge);
      continue;
    }
    const bool known = !core::check_uav_id(st.uav, scenario_.uavs);
    bool adopted = true;
    if (known && core::home_region(st.uav, geo_.region_count()) != cfg_.region) {
      // A UAV whose backup this region is: realtime, it judged its home dead
      // and came here; lockstep, only once the clock lists its home absent
      // (note_absent adopted it). Anyone else's: a stray or forged writer.
      if (core::backup_region(st.uav, geo_.region_count()) != cfg_.region) {
        audit_.refuse(core::Refusal::ImplausibleState,
                      fmt::format("a state of uav {} at place agent {}, which is neither its home nor its backup{}",
                                  st.uav, cfg_.region, carried_note()));
        continue;
      }
      if (!cfg_.common.lockstep()) adopt(st.uav, nullptr);
      adopted = adopted_.contains(st.uav);
    }
    // Before the motion check: a forged state must not become the UAV's
    // last accepted one.
    if (known && !state_writers_.allows(st.uav, st.writer, now)) {
      refuse_foreign_state(st.uav);
      continue;
    }
    if (!adopted) {  // lockstep: its state counts from the tick its home is absent
      route_carried(core::CarriedDeposits::Judge);
      continue;
    }
    const core::UavStateMsg* before = views_.state(st.uav);
    const auto judged =
        gate_.judge(st, before, core::uav_start(scenario_, traits_, st.uav), traits_.max_step, ceiling, rules_);
    route_carried(core::carried_deposits(judged));  // no deposit of a refused state goes on
    if (judged.refused_motion) {
      // The UAV flew (or says it flew) further than its policy's max_step
      // allows: refused, counted once per tick, and answered.
      if (!judged.copy) (void)audit_.admit(judged.verdict);
      answer_refused(st);
      continue;
    }
    if (!audit_.admit(judged.verdict)) continue;
    state_writers_.hold(st.uav, st.writer, now);
    uav_process_[st.uav] = st.participant;
    if (before == nullptr || st.tick > before->tick) heard_at_[st.uav] = tick;
    views_.update_state(st);
    // The ground station hears the UAVs through their gateways (relays),
    // all those of this take in one sample (below).
    relayed_.push_back(st);
    ++states_relayed_;
  }
  departed_.clear();
  bus_->take_departed_uavs(departed_);
  for (const auto& d : departed_) {
    const uint32_t u = d.uav;
    state_writers_.release(u);  // every state writer of u vanished: the next one heard is u
    uav_process_.erase(u);
    if (std::find(gateway_uavs_.begin(), gateway_uavs_.end(), u) == gateway_uavs_.end()) continue;
    core::UavStateMsg gone;
    gone.uav = u;
    if (const core::UavStateMsg* last = views_.state(u)) gone = *last;
    gone.departed = true;
    relayed_.push_back(gone);
    log_->info(
        "uav {} departed (its state writer's liveliness lapsed: it died, hangs or its packets were lost); told "
        "the ground station",
        u);
  }
  if (!relayed_.empty()) bus_->relay_states(relayed_, cfg_.region, cfg_.replica, tick);
}

void PlaceApp::answer_refused(const core::UavStateMsg& st) {
  relayed_.push_back(core::refused_answer(st));
  if (std::find(refused_views_.begin(), refused_views_.end(), st.uav) == refused_views_.end()) {
    refused_views_.push_back(st.uav);
  }
}

void PlaceApp::refuse_foreign_state(uint32_t uav) {
  audit_.refuse(core::Refusal::ForeignWriter,
                fmt::format("a state of uav {} from a writer other than the one this place agent heard it from first "
                            "(and still hears){}",
                            uav, carried_note()));
}

std::string PlaceApp::carried_note() const {
  if (carried_.empty()) return {};
  return fmt::format(", and the {} deposit{} it carried", carried_.size(), carried_.size() == 1 ? "" : "s");
}

void PlaceApp::relay_uplinks() {
  relay_reports();
  // Detections and broadcasts of the UAVs it serves, up; the swarm's
  // broadcasts (its own UAVs' among them, as it relayed them to "b"), down.
  detections_up_.clear();
  bus_->take_uplink_detections(detections_up_);
  const auto now = Clock::now();
  for (const auto& d : detections_up_) {
    // Only of a UAV this place agent can be the gateway of (as its states),
    // from the UAV's own process: the one that writes its states.
    if (audit_.admit(core::judge_uplink("a detection", d.uav, cfg_.region, names_,
                                        from_uav_process(d.uav, d.participant, now),
                                        core::Refusal::ImplausibleDetection, core::Refusal::ForeignWriter))) {
      bus_->relay_detection(d);
    }
  }
  // A broadcast goes on only if it is well formed and of a UAV of the swarm.
  const auto admitted = [&](const core::BroadcastMsg& b) {
    if (core::check_broadcast(b)) {
      audit_.drop(fmt::format("a malformed broadcast of uav {}", b.uav));
      return false;
    }
    if (core::check_uav_id(b.uav, scenario_.uavs)) {
      audit_.refuse(core::Refusal::UnknownUav, fmt::format("a broadcast of uav {}", b.uav));
      return false;
    }
    return true;
  };
  broadcasts_.clear();
  bus_->take_uplink_broadcasts(broadcasts_);
  for (const auto& b : broadcasts_) {
    if (!admitted(b)) continue;
    if (!from_uav_process(b.uav, b.participant, now)) {
      audit_.refuse(core::Refusal::ForeignWriter,
                    fmt::format("a broadcast of uav {} from a process other than the one its states come from", b.uav));
      continue;
    }
    bus_->relay_broadcast_up(b);
  }
  broadcasts_.clear();
  bus_->take_broadcasts(broadcasts_);
  for (const auto& b : broadcasts_) {
    if (admitted(b)) bus_->relay_broadcast_down(b);
  }
  // The ground station's commands, as this place agent admitted them
  // (each UAV checks their signatures again).
  for (const auto& c : commands_->take()) bus_->relay_command(c);
}

uint32_t PlaceApp::home_states_of(uint32_t tick) const {
  // A refused state is an answer too (core::StateGate).
  return static_cast<uint32_t>(std::count_if(gateway_uavs_.begin(), gateway_uavs_.end(), [&](uint32_t u) {
    const core::UavStateMsg* st = views_.state(u);
    const auto refused = gate_.refused_tick(u);
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

void PlaceApp::take_inputs(uint32_t tick) {
  inbox_.clear();
  take_home_states(tick);  // first: the states carry their UAVs' deposits
  take_deposits();
  if (!demand_) return;
  // Lockstep: exactly the deposits the UAVs reported for this region and the
  // states of the home UAVs that took part in the UAV phase, as the clock
  // announced, and every deposit those home UAVs wrote (some to forward,
  // holds_home_deposits). Waiting for these exact samples replaces the UAVs' wait for
  // acknowledgements. Forged deposits carrying this tick must not stand in
  // for real ones (the place would apply the tick before all of them arrived).
  // Meanwhile the deposits forwarded so far go out again after a quiet spell:
  // two place agents each waiting for the other's lost forward would
  // otherwise wait for each other.
  const auto deposits = [&] {
    return static_cast<uint32_t>(std::count_if(
        inbox_.begin(), inbox_.end(), [&](const auto& d) { return d.tick == tick && !core_.refuses(d, tick); }));
  };
  const auto r = runtime::await_samples(
      *bus_, {bus::TopicKind::Deposit, bus::TopicKind::UavHome}, {}, &resend_,
      [&] {
        keep_tree();  // the lockstep tree goes on while this phase waits
        take_home_states(tick);
        take_deposits();
      },
      [&] {
        return deposits() >= demand_->deposits && home_states_of(tick) >= demand_->states && holds_home_deposits(tick);
      });
  if (r != runtime::Awaited::Done) {
    log_->error("tick {}: {} of {} announced deposits and {} of {} home UAV states arrived{}; applying those", tick,
                deposits(), demand_->deposits, home_states_of(tick), demand_->states,
                holds_home_deposits(tick) ? "" : ", not every deposit of the home UAVs to forward");
  }
}

void PlaceApp::exchange_halos(uint32_t tick) {
  // Neighbour rings. Realtime: whatever arrived (a neighbour that sent
  // nothing new leaves its last ring in the halo, counted as missing).
  // Lockstep: exactly the rings of this tick; an absent neighbour's last ring
  // stays in the halo (frozen).
  std::set<core::RegionId> fresh;
  const auto& neighbours = core_.neighbours();
  const auto awaited = static_cast<std::size_t>(
      std::count_if(neighbours.begin(), neighbours.end(), [&](core::RegionId n) { return !is_absent(n); }));
  const auto take = [&] {
    keep_tree();  // the lockstep tree goes on while this phase waits
    halo_inbox_.clear();
    bus_->take_halos(halo_inbox_);
    const uint32_t ceiling = tick_ceiling();
    for (const auto& h : halo_inbox_) {
      // Lockstep: a ring of an earlier tick is a late re-send (no news); one
      // of a later tick cannot exist while this place agent has not reported
      // this tick's phase done, so the conductor has not begun the next.
      if (demand_ && (h.tick < tick || is_absent(h.region))) continue;
      if (demand_ && h.tick > tick) {
        audit_.refuse(
            core::Refusal::TickFarAhead,
            fmt::format("a halo ring of region {} for tick {} in the place phase of tick {}", h.region, h.tick, tick));
        continue;
      }
      const auto whole = core::expand_halo(h, geo_, cfg_.region);
      if (auto reason = core::check_tick_reachable(h.tick, ceiling, "halo")) {
        audit_.refuse(core::Refusal::TickFarAhead, *reason);
      } else if (!whole || !core_.accept_halo(*whole)) {
        log_->warn("dropped malformed or out-of-range halo from region {}", h.region);
      } else {
        fresh.insert(h.region);
      }
    }
  };
  const auto r = runtime::await_samples(*bus_, {bus::TopicKind::Halo}, {}, &resend_, take,
                                        [&] { return !demand_ || fresh.size() >= awaited; });
  if (r != runtime::Awaited::Done) {
    log_->error("tick {}: rings of {} of {} neighbours did not arrive", tick, awaited - std::min(awaited, fresh.size()),
                awaited);
  }
  halos_missing_ += awaited - std::min(fresh.size(), awaited);
}

void PlaceApp::publish_served(uint32_t tick) {
  // The home UAVs that get a view this tick and where they are, to every
  // other place agent: each owner sends back the tiles their views need.
  // Lockstep: those that took part in this tick's UAV phase.
  served_.clear();
  served_states_.clear();
  for (uint32_t u : gateway_uavs_) {
    const core::UavStateMsg* st = views_.state(u);
    if (st == nullptr || st->finished) continue;
    if (demand_ ? st->tick != tick : tick - heard_at_[u] > kViewsAfterSilence) continue;
    // Its newest state was refused: it gets an empty view (serve_views), not
    // one around a position it has left.
    if (const auto refused = gate_.refused_tick(u); refused && *refused > st->tick) continue;
    served_.push_back(u);
    served_states_.push_back(*st);
  }
  for (auto& f : core::make_field_chunks(cfg_.region, tick, {}, served_states_)) {
    f.replica = cfg_.replica;
    resend_.served(f);
  }
}

void PlaceApp::take_served(uint32_t tick) {
  // Which UAVs every other place agent serves and where they are: exactly
  // this tick's (lockstep). Before the deposits are applied: they are judged
  // against these positions (deposit_reach).
  const auto take = [&] {
    keep_tree();  // the lockstep tree goes on while this phase waits
    field_inbox_.clear();
    bus_->take_served(field_inbox_);
    const uint32_t ceiling = tick_ceiling();
    const auto now = Clock::now();
    for (const auto& f : field_inbox_) {
      if (f.region == cfg_.region || !audit_.admit(core::check_field_chunk(f, ceiling, rules_))) continue;
      // What only that place agent writes, judged by who wrote it; it
      // vouches for its process as a forwarder of deposits (judge_forwarded).
      forwarders_.heard(core::place_id(f.region, f.replica), f.participant, now);
      if (audit_.admit(core::judge_place_sample(forwarders_, f.region, f.replica, f.participant, now, names_, false,
                                                "a served-UAVs chunk"))) {
        views_.update_served(f, tick);
      }
    }
  };
  const auto r = runtime::await_samples(*bus_, {bus::TopicKind::Field}, {}, &resend_, take,
                                        [&] { return !demand_ || views_.holds_served(tick, present_others_); });
  if (r != runtime::Awaited::Done) {
    log_->error("tick {}: the served UAVs of some regions did not arrive ({}); sending tiles for the latest", tick,
                views_.missing_served(tick, present_others_));
  }
}

void PlaceApp::send_tiles(uint32_t tick) {
  take_served(tick);  // held since before the deposits were applied (step); realtime: what came since
  // To each of them the tiles of this region their UAVs' views need, and nothing else.
  std::map<std::pair<int32_t, int32_t>, std::vector<std::size_t>> by_tile;
  for (std::size_t i = 0; i < tiles_out_.size(); ++i)
    by_tile[{tiles_out_[i].tile.tx, tiles_out_[i].tile.ty}].push_back(i);
  // Realtime: not to a place agent not heard of lately (it died: its views
  // are no one's).
  const uint32_t heard_since = demand_ || tick < tiles_stale_after_ ? 0 : tick - tiles_stale_after_;
  for (core::RegionId home : present_others_) {
    const std::vector<uint32_t> uavs = views_.served_by(home, heard_since);
    tiles_for_.clear();
    for (const core::TileCoord t : views_.needed_tiles(uavs, tile_margin())) {
      auto it = by_tile.find({t.tx, t.ty});
      if (it == by_tile.end()) continue;  // another region's tile
      for (std::size_t i : it->second) tiles_for_.push_back(tiles_out_[i]);
    }
    if (tiles_for_.empty()) continue;
    for (auto& f : core::make_field_chunks(cfg_.region, tick, tiles_for_, {})) {
      f.replica = cfg_.replica;
      resend_.tiles_for(f, home);
    }
  }
}

std::vector<core::RegionId> PlaceApp::owners_for_views() const {
  // The other present regions whose tiles the served UAVs' views need: they
  // send them (send_tiles above, from the same served states).
  std::set<core::RegionId> owners;
  for (const core::TileCoord t : views_.needed_tiles(served_, tile_margin())) {
    const core::RegionId r = geo_.region_of_tile(t);
    if (r != cfg_.region && !is_absent(r)) owners.insert(r);
  }
  return {owners.begin(), owners.end()};
}

void PlaceApp::receive_tiles(uint32_t tick) {
  // Lockstep waits for exactly these owners; realtime takes what arrived.
  const std::vector<core::RegionId> owners = demand_ ? owners_for_views() : std::vector<core::RegionId>{};
  const auto take = [&] {
    keep_tree();  // the lockstep tree goes on while this phase waits
    field_inbox_.clear();
    bus_->take_tiles_for_views(field_inbox_);
    const uint32_t ceiling = tick_ceiling();
    for (const auto& f : field_inbox_) {
      if (f.region == cfg_.region || !audit_.admit(core::check_field_chunk(f, ceiling, rules_))) continue;
      // Lockstep shows a tile of this tick only; realtime one that arrived lately.
      views_.update_tiles(f, demand_ ? f.tick : tick);
    }
  };
  const auto r = runtime::await_samples(*bus_, {bus::TopicKind::Field}, {}, &resend_, take,
                                        [&] { return !demand_ || views_.holds_tiles(tick, owners); });
  if (r != runtime::Awaited::Done) {
    log_->error("tick {}: the tiles of some regions did not arrive ({}); views go without them", tick,
                views_.missing_tiles(tick, owners));
  }
}

void PlaceApp::serve_views(uint32_t tick) {
  for (const auto& t : tiles_out_) views_.update_tile(t, tick);
  // This region's field (core::FieldToGround: lockstep all of it every tick,
  // realtime what changed at the console's rate) and its home UAVs' latest
  // states, to the ground station.
  if (to_ground_.due(tick, last_tick_)) {
    home_states_.clear();
    for (uint32_t u : gateway_uavs_) {
      if (const core::UavStateMsg* st = views_.state(u)) home_states_.push_back(*st);
    }
    ground_tiles_.clear();
    to_ground_.select(tiles_out_, last_tick_, ground_tiles_);
    for (auto& f : core::make_field_chunks(cfg_.region, tick, ground_tiles_, home_states_)) {
      f.replica = cfg_.replica;
      resend_.field(f);
    }
  }
  send_tiles(tick);
  receive_tiles(tick);
  // Lockstep: tiles of this tick only; realtime: tiles an owner sent lately
  // (a dead owner's region goes dark after that).
  const uint32_t min_tile_tick = demand_ ? tick : (tick > tiles_stale_after_ ? tick - tiles_stale_after_ : 0);
  for (uint32_t u : served_) {
    if (views_.compose(u, tick, demand_ ? 0 : kNeighbourAge, min_tile_tick, view_)) {
      view_.deposit_ack = desk_.ack(u);
      view_.deposit_ack_from = desk_.ack_from(u);
      resend_.view(view_);
    }
  }
  // A UAV whose state was refused gets an empty view of this tick: no tile
  // and no neighbour around a position its gateway does not believe, and in
  // lockstep the answer it waits for (the simulator does the same).
  for (uint32_t u : refused_views_) {
    view_.uav = u;
    view_.tick = tick;
    view_.tiles.clear();
    view_.uavs.clear();
    view_.deposit_ack = desk_.ack(u);
    view_.deposit_ack_from = desk_.ack_from(u);
    resend_.view(view_);
  }
  refused_views_.clear();
}

void PlaceApp::step(uint32_t tick, std::optional<TickDemand> demand) {
  current_tick_ = tick;
  demand_ = demand;
  resend_.begin_tick();
  take_inputs(tick);
  publish_served(tick);
  events_.clear();
  rejections_.clear();
  take_served(tick);
  // Each deposit where its UAV can have put it, judged against the UAV's
  // last accepted state this place agent knows (its own home UAVs' and every
  // other region's served UAVs'; the simulator judges the same way).
  const core::PlaceCore::DepositReach reach = [&](const core::DepositMsg& d) {
    return core::check_deposit_reach(d, views_.state(d.uav), core::uav_start(scenario_, traits_, d.uav),
                                     traits_.max_step, traits_.deposit_reach);
  };
  const core::HaloRing ring = core_.begin_tick(inbox_, tick, events_, &rejections_, &reach);
  for (const auto& r : rejections_) {
    if (core_.ledger().rejected() <= 20) log_->warn("rejected deposit from {}", r);
  }
  for (const auto& e : events_) {
    bus_->publish_target_event(e);
    log_->info("target at ({},{}) {} at tick {}", e.cell.x, e.cell.y,
               core::to_string(static_cast<core::TargetEventKind>(e.kind)), tick);
  }
  // To each neighbour only the cells of the ring its diffusion reads. With
  // shared ownership each replica writes an instance of its own (keyed by
  // replica): two writers of one keep-last-1 instance let a reader's history
  // replace or drop one replica's ring by the other's (on Fast DDS 2.9 by
  // source timestamp, DataReaderHistory::received_change_keep_last), and a
  // standby then waited 30 s for a ring (docs/faults.md). The receiver takes
  // the ring of the tick from whichever replica's instance has it.
  const uint16_t halo_key = replicated_ && cfg_.common.shared_ownership ? cfg_.replica : 0;
  const core::HaloMsg full{cfg_.region, tick, ring.target, ring.obstacle, halo_key};
  for (core::RegionId n : core_.neighbours()) {
    if (!is_absent(n)) resend_.halo(core::trim_halo(full, geo_, n), n);
  }
  exchange_halos(tick);
  core_.finish_tick();
  tiles_out_.clear();
  core_.tiles(tick, core::PlaceCore::TileSelection::All, tiles_out_);
  serve_views(tick);
}

}  // namespace pheromesh::placeagent
