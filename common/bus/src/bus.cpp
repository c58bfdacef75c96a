// The role wiring of the bus, once for every transport: which endpoints a
// UAV, a place agent, the ground station and the conductor open, and the
// thin publish_* / take_* wrappers of those typed endpoints.
#include "pheromesh/bus/bus.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <iterator>
#include <optional>
#include <utility>

#include "pheromesh/bus/routing.hpp"
#include "pheromesh/bus/typed.hpp"

namespace pheromesh::bus {

using namespace routing;  // NOLINT: partition names

struct Bus::Roles {
  explicit Roles(Bus& b)
      : tiles(b),
        deposits(b),
        states(b),
        views(b),
        fields(b),
        detections(b),
        events(b),
        health(b),
        halos(b),
        broadcasts(b),
        clock(b),
        relayed_clock(b, TopicKind::RelayedClock),
        ground_states(b, TopicKind::GroundState),
        place_fields(b, TopicKind::PlaceField),
        phase_done(b),
        commands(b),
        scenarios(b) {}

  Writer<core::TileMsg> tiles;
  Writer<core::DepositBatchMsg> deposits;
  Writer<core::UavStateMsg> states;
  Writer<core::ViewMsg> views;
  Writer<core::FieldMsg> fields;
  Writer<core::DetectionMsg> detections;
  Writer<core::TargetEventMsg> events;
  Writer<core::HealthMsg> health;
  Writer<core::HaloMsg> halos;
  Writer<core::BroadcastMsg> broadcasts;
  Writer<core::ClockMsg> clock;
  Writer<core::ClockMsg> relayed_clock;  // a place agent's, to the UAVs it serves
  Writer<core::FieldMsg> ground_states;  // a place agent's, relaying its UAVs' states to the ground (batched)
  Writer<core::FieldMsg> place_fields;   // a place agent's, to the others: served UAVs, tiles for views
  Writer<core::PhaseDoneMsg> phase_done;
  Writer<core::CommandMsg> commands;
  Writer<core::ScenarioMsg> scenarios;

  std::optional<core::RegionId> home;  // a UAV's home place agent (join_uav)
  bool clock_tree = false;             // a lockstep UAV (join_clock_tree)
  bool broadcaster = false;            // a UAV whose policy broadcasts (join_uav)
  std::vector<core::RegionId> gateways;  // a UAV's downlinks (join_gateways)
  std::optional<core::RegionId> relay_for;  // a place agent's region (subscribe_uplinks)

  std::optional<Reader<core::ViewMsg>> view_in;
  std::optional<Reader<core::FieldMsg>> field_in, served_in, tiles_in;
  std::optional<Reader<core::UavStateMsg>> home_states_in;
  std::optional<Reader<core::FieldMsg>> ground_states_in;
  std::optional<Reader<core::DepositBatchMsg>> deposit_in;
  std::vector<core::DepositBatchMsg> batches_in;  // take_deposits' scratch
  std::optional<Reader<core::HaloMsg>> halo_in;
  std::optional<Reader<core::TileMsg>> tile_in;
  std::optional<Reader<core::DetectionMsg>> detection_in, detection_up_in;
  std::optional<Reader<core::TargetEventMsg>> event_in;
  std::optional<Reader<core::HealthMsg>> health_in;
  std::optional<Reader<core::ClockMsg>> clock_in;
  std::optional<Reader<core::PhaseDoneMsg>> done_in, reports_in;
  std::optional<Reader<core::BroadcastMsg>> broadcast_in, broadcast_up_in;
  std::optional<Reader<core::CommandMsg>> command_in;
  std::optional<Reader<core::ScenarioMsg>> scenario_in;

  std::vector<uint32_t> departed_uavs;  // a place agent's home UAVs, as its reader saw them
  std::vector<core::UavDeparture> relayed_departures;  // the ground station's, as the place agents relayed them
  std::vector<core::PhaseDoneMsg> relayed_reports;     // the ground station's, relayed with the states
  std::vector<uint32_t> departed_regions;  // core::place_id
};

Bus::Bus(std::unique_ptr<Transport> transport)
    : transport_(std::move(transport)), roles_(std::make_unique<Roles>(*this)) {}

// The roles' endpoints before the transport that made them.
Bus::~Bus() { roles_.reset(); }

std::string Bus::vendor() const { return transport_->vendor(); }

bool Bus::refuse(const Oversize& o) {
  ++writes_refused_;
  spdlog::default_logger()->warn("refusing to write {} with {} elements: over the IDL bound", o.what, o.n);
  return false;
}

void Bus::opened(TopicKind kind, Endpoint endpoint, EndpointId id) {
  (endpoint == Endpoint::Writer ? writers_ : readers_).emplace_back(kind, id);
}

BusStats Bus::stats() const {
  BusStats s = transport_->stats();
  s.writes_refused += writes_refused_;
  s.samples_taken += samples_taken_;
  s.bytes_taken += bytes_taken_;
  return s;
}

// ------------------------------------------------------------------ publish
bool Bus::publish_tile(const core::TileMsg& m) { return roles_->tiles.write(m); }
bool Bus::publish_deposits(const core::DepositBatchMsg& m, core::RegionId via) {
  return roles_->deposits.write(m, region_partition(via));
}

bool Bus::publish_deposit(const core::DepositMsg& m, core::RegionId via) {
  return publish_deposits({roles_->relay_for.value_or(0), m.tick, {m}}, via);
}
bool Bus::publish_uav_state(const core::UavStateMsg& m) {
  if (!roles_->home) throw BusMisuse("publish_uav_state before join_uav");
  return roles_->states.write(m, home_partition(*roles_->home));
}
bool Bus::publish_view(const core::ViewMsg& m) { return roles_->views.write(m); }
bool Bus::publish_field(const core::FieldMsg& m) { return roles_->fields.write(m); }
bool Bus::publish_served(const core::FieldMsg& m) { return roles_->place_fields.write(m, kServedPartition); }
bool Bus::publish_tiles_for(const core::FieldMsg& m, core::RegionId home) {
  return roles_->place_fields.write(m, tiles_for_partition(home));
}
bool Bus::publish_detection(const core::DetectionMsg& m) {
  if (roles_->home) return roles_->detections.write(m, detection_uplink_partition(*roles_->home));
  return roles_->detections.write(m);
}
bool Bus::publish_target_event(const core::TargetEventMsg& m) { return roles_->events.write(m); }
bool Bus::publish_health(const core::HealthMsg& m) { return roles_->health.write(m); }
bool Bus::publish_halo(const core::HaloMsg& m, core::RegionId to) {
  return roles_->halos.write(m, halo_partition(m.region, to));
}
bool Bus::publish_broadcast(const core::BroadcastMsg& m) {
  if (roles_->home) return roles_->broadcasts.write(m, broadcast_uplink_partition(*roles_->home));
  return roles_->broadcasts.write(m);
}
bool Bus::relay_detection(const core::DetectionMsg& m) { return roles_->detections.write(m, kGroundPartition); }
bool Bus::relay_broadcast_up(const core::BroadcastMsg& m) { return roles_->broadcasts.write(m, kBroadcastPartition); }
bool Bus::relay_broadcast_down(const core::BroadcastMsg& m) {
  if (!roles_->relay_for) throw BusMisuse("relay_broadcast_down before subscribe_uplinks");
  return roles_->broadcasts.write(m, broadcast_downlink_partition(*roles_->relay_for));
}
bool Bus::relay_command(const core::CommandMsg& m) {
  if (!roles_->relay_for) throw BusMisuse("relay_command before subscribe_uplinks");
  return roles_->commands.write(m, command_downlink_partition(*roles_->relay_for));
}
bool Bus::relay_states(std::span<const core::UavStateMsg> states, core::RegionId own, uint16_t replica, uint32_t tick,
                       std::span<const core::PhaseDoneMsg> reports) {
  // One sample per kMaxFieldUavs states and reports (one in any swarm the
  // bounds allow a place agent to serve), not one per state and report;
  // each report in the sample of its state or after it.
  bool ok = true;
  std::size_t state = 0, report = 0;
  while (state < states.size() || report < reports.size()) {
    const std::size_t n = std::min(core::kMaxFieldUavs, states.size() - state);
    const std::size_t r = state + n < states.size() ? 0 : std::min(core::kMaxFieldUavs, reports.size() - report);
    core::FieldMsg batch;
    batch.region = own;
    batch.chunks = 1;
    batch.tick = tick;
    batch.replica = replica;
    batch.uavs.assign(states.begin() + static_cast<std::ptrdiff_t>(state),
                      states.begin() + static_cast<std::ptrdiff_t>(state + n));
    batch.reports.assign(reports.begin() + static_cast<std::ptrdiff_t>(report),
                         reports.begin() + static_cast<std::ptrdiff_t>(report + r));
    state += n;
    report += r;
    ok = roles_->ground_states.write(batch, kGroundPartition) && ok;
  }
  return ok;
}
bool Bus::publish_clock(const core::ClockMsg& m) { return roles_->clock.write(m); }
bool Bus::publish_phase_done(const core::PhaseDoneMsg& m) {
  if (roles_->clock_tree) return roles_->phase_done.write(m, uav_report_partition(*roles_->home));
  return roles_->phase_done.write(m);
}
bool Bus::relay_clock(const core::ClockMsg& m, core::RegionId own) {
  return roles_->relayed_clock.write(m, uav_clock_partition(own));
}
bool Bus::relay_clock_to_backups(const core::ClockMsg& m, core::RegionId own) {
  return roles_->relayed_clock.write(m, uav_backup_clock_partition(own));
}
bool Bus::publish_command(const core::CommandMsg& m) { return roles_->commands.write(m); }
bool Bus::publish_scenario(const core::ScenarioMsg& m) { return roles_->scenarios.write(m); }

// ------------------------------------------------------------------- roles
void Bus::join_uav(uint32_t uav, core::RegionId home, bool broadcasts) {
  roles_->home = home;
  roles_->states.offer(home_partition(home));  // its state and its deposits (UavStateMsg::deposits)
  roles_->detections.offer(detection_uplink_partition(home));
  roles_->broadcaster = broadcasts;
  if (broadcasts) roles_->broadcasts.offer(broadcast_uplink_partition(home));
  roles_->view_in.emplace(*this, std::vector<std::string>{view_partition(uav)});
}

void Bus::join_gateways(std::span<const core::RegionId> gateways) {
  if (!roles_->home) throw BusMisuse("join_gateways before join_uav");
  roles_->gateways.clear();
  for (auto r : gateways) {
    if (std::find(roles_->gateways.begin(), roles_->gateways.end(), r) == roles_->gateways.end()) {
      roles_->gateways.push_back(r);
    }
  }
}

void Bus::subscribe_uplinks(core::RegionId own) {
  roles_->relay_for = own;
  roles_->detection_up_in.emplace(*this, std::vector<std::string>{detection_uplink_partition(own)});
  roles_->broadcast_up_in.emplace(*this, std::vector<std::string>{broadcast_uplink_partition(own)});
  if (!roles_->broadcast_in) roles_->broadcast_in.emplace(*this, std::vector<std::string>{kBroadcastPartition});
  roles_->ground_states.offer(kGroundPartition);
  roles_->detections.offer(kGroundPartition);
  roles_->broadcasts.offer(kBroadcastPartition);
  roles_->broadcasts.offer(broadcast_downlink_partition(own));
  roles_->commands.offer(command_downlink_partition(own));
}

bool Bus::move_uplink(core::RegionId gateway) {
  if (!roles_->home) throw BusMisuse("move_uplink before join_uav");
  // Before the new writers: they are then made once, in the new participant.
  const bool reached = transport_->reach_reserve();
  roles_->home = gateway;
  roles_->states.offer(home_partition(gateway));
  roles_->detections.offer(detection_uplink_partition(gateway));
  if (roles_->broadcaster) roles_->broadcasts.offer(broadcast_uplink_partition(gateway));
  if (roles_->clock_tree) roles_->phase_done.offer(uav_report_partition(gateway));
  return reached;
}

void Bus::subscribe_deposits(core::RegionId own, bool history) {
  roles_->deposit_in.emplace(*this, std::vector<std::string>{region_partition(own)}, TopicKind::Deposit,
                             history ? Watch::Samples : Watch::NewSamplesOnly);
}

void Bus::subscribe_home_states(core::RegionId own, bool history) {
  // The home place agent's reader of the UAVs' state writers: its own QoS
  // row. It tells the ground station of their departures (relay_state).
  // The states carry the UAVs' deposits: a place agent started again takes
  // none its dead life counted (as subscribe_deposits).
  roles_->home_states_in.emplace(*this, std::vector<std::string>{home_partition(own)}, TopicKind::UavHome,
                                 history ? Watch::SamplesAndDepartures : Watch::NewSamplesAndDepartures);
}

void Bus::subscribe_fields() { roles_->field_in.emplace(*this, std::vector<std::string>{kFieldPartition}); }

void Bus::subscribe_place_exchange(core::RegionId own, bool served) {
  if (served) roles_->served_in.emplace(*this, std::vector<std::string>{kServedPartition}, TopicKind::PlaceField);
  roles_->tiles_in.emplace(*this, std::vector<std::string>{tiles_for_partition(own)}, TopicKind::PlaceField);
}

void Bus::offer_place_exchange(std::span<const core::RegionId> others, bool served) {
  if (served) roles_->place_fields.offer(kServedPartition);
  for (auto r : others) roles_->place_fields.offer(tiles_for_partition(r));
}

void Bus::offer_views(std::span<const uint32_t> uavs) {
  for (uint32_t u : uavs) roles_->views.offer(view_partition(u));
}

void Bus::subscribe_halos(std::span<const core::RegionId> neighbours, core::RegionId own) {
  std::vector<std::string> parts;
  for (auto r : neighbours) parts.push_back(halo_partition(r, own));
  if (!parts.empty()) roles_->halo_in.emplace(*this, parts);
}

void Bus::subscribe_ground() {
  const std::vector<std::string> ground{kGroundPartition};
  roles_->tile_in.emplace(*this, std::vector<std::string>{kAllTiles});
  // The UAVs' states and departures, as their place agents relay them.
  roles_->ground_states_in.emplace(*this, ground, TopicKind::GroundState);
  roles_->detection_in.emplace(*this, ground);
  roles_->event_in.emplace(*this, ground);
  subscribe_health();
  subscribe_fields();
}

void Bus::subscribe_health() {
  roles_->health_in.emplace(*this, std::vector<std::string>{kGroundPartition}, TopicKind::Health,
                            Watch::SamplesAndDepartures);
}

namespace {
std::vector<std::string> downlinks(const std::vector<core::RegionId>& gateways,
                                   std::string (*partition)(core::RegionId)) {
  std::vector<std::string> parts;
  for (auto r : gateways) parts.push_back(partition(r));
  return parts;
}
}  // namespace

void Bus::subscribe_broadcasts() {
  if (!roles_->gateways.empty()) {
    roles_->broadcast_in.emplace(*this, downlinks(roles_->gateways, broadcast_downlink_partition));
  } else if (!roles_->broadcast_in) {  // a place agent reads "b" already (subscribe_uplinks)
    roles_->broadcast_in.emplace(*this, std::vector<std::string>{kBroadcastPartition});
  }
}
void Bus::subscribe_clock() { roles_->clock_in.emplace(*this, std::vector<std::string>{kClockPartition}); }
void Bus::join_clock_tree(std::span<const core::RegionId> gateways) {
  if (!roles_->home) throw BusMisuse("join_clock_tree before join_uav");
  roles_->clock_tree = true;
  roles_->phase_done.offer(uav_report_partition(*roles_->home));
  std::vector<std::string> parts;
  for (std::size_t i = 0; i < gateways.size(); ++i) {
    if (i > 0 && gateways[i] == gateways[0]) continue;  // one region: its home backs it up too
    const std::string p = i == 0 ? uav_clock_partition(gateways[i]) : uav_backup_clock_partition(gateways[i]);
    if (std::find(parts.begin(), parts.end(), p) == parts.end()) parts.push_back(p);
  }
  roles_->clock_in.emplace(*this, parts, TopicKind::RelayedClock);
}
void Bus::subscribe_uav_reports(core::RegionId own) {
  offer_phase_done();  // its own reports and those it relays
  roles_->relayed_clock.offer(uav_clock_partition(own));
  roles_->relayed_clock.offer(uav_backup_clock_partition(own));
  roles_->reports_in.emplace(*this, std::vector<std::string>{uav_report_partition(own)});
}
void Bus::offer_phase_done() { roles_->phase_done.offer(kClockPartition); }
void Bus::subscribe_phase_done() { roles_->done_in.emplace(*this, std::vector<std::string>{kClockPartition}); }
void Bus::subscribe_commands() {
  if (!roles_->gateways.empty()) {
    roles_->command_in.emplace(*this, downlinks(roles_->gateways, command_downlink_partition));
  } else {
    roles_->command_in.emplace(*this, std::vector<std::string>{kCommandPartition});
  }
}
void Bus::subscribe_scenario() { roles_->scenario_in.emplace(*this, std::vector<std::string>{kGroundPartition}); }

// -------------------------------------------------------------------- take
namespace {
// Takes from `reader` if the role subscribed it; keeps the writers alive
// either way (every take_* call does, qos.hpp).
template <typename M>
void take_from(Transport& t, std::optional<Reader<M>>& reader, std::vector<M>& out) {
  if (reader) {
    reader->take(out);
  } else {
    t.keep_alive();
  }
}
}  // namespace

void Bus::take_deposits(std::vector<core::DepositMsg>& out) {
  auto& batches = roles_->batches_in;
  batches.clear();
  take_from(*transport_, roles_->deposit_in, batches);
  for (auto& b : batches) {
    for (auto& d : b.deposits) {
      d.participant = b.participant;
      out.push_back(d);
    }
  }
}
void Bus::take_halos(std::vector<core::HaloMsg>& out) { take_from(*transport_, roles_->halo_in, out); }
void Bus::take_tiles(std::vector<core::TileMsg>& out) { take_from(*transport_, roles_->tile_in, out); }
void Bus::take_fields(std::vector<core::FieldMsg>& out) { take_from(*transport_, roles_->field_in, out); }
void Bus::take_served(std::vector<core::FieldMsg>& out) { take_from(*transport_, roles_->served_in, out); }
void Bus::take_tiles_for_views(std::vector<core::FieldMsg>& out) { take_from(*transport_, roles_->tiles_in, out); }
void Bus::take_views(std::vector<core::ViewMsg>& out) {
  out.insert(out.end(), std::make_move_iterator(held_views_.begin()), std::make_move_iterator(held_views_.end()));
  held_views_.clear();
  const std::size_t first = out.size();
  take_from(*transport_, roles_->view_in, out);
  lift_clocks(out, first);
}
void Bus::lift_clocks(std::vector<core::ViewMsg>& views, std::size_t first) {
  for (std::size_t i = first; i < views.size(); ++i) {
    auto& v = views[i];
    if (!v.clock) continue;
    // Only a lockstep UAV takes a clock from its view, and only as the
    // process that wrote the view (0: the vendor no longer knows it).
    if (roles_->clock_tree && v.participant != 0) {
      v.clock->writer = v.participant;
      v.clock->participant = v.participant;
      view_clocks_.push_back(std::move(*v.clock));
    }
    v.clock.reset();
  }
}
void Bus::take_detections(std::vector<core::DetectionMsg>& out) { take_from(*transport_, roles_->detection_in, out); }
void Bus::take_uplink_detections(std::vector<core::DetectionMsg>& out) {
  take_from(*transport_, roles_->detection_up_in, out);
}
void Bus::take_uplink_broadcasts(std::vector<core::BroadcastMsg>& out) {
  take_from(*transport_, roles_->broadcast_up_in, out);
}
void Bus::take_target_events(std::vector<core::TargetEventMsg>& out) { take_from(*transport_, roles_->event_in, out); }
void Bus::take_broadcasts(std::vector<core::BroadcastMsg>& out) { take_from(*transport_, roles_->broadcast_in, out); }
void Bus::take_clock(std::vector<core::ClockMsg>& out) {
  if (!roles_->clock_tree) {
    take_from(*transport_, roles_->clock_in, out);
    return;
  }
  // A UAV: the clocks in its views too (the views wait for take_views). A
  // place agent relays the clock through its relay writer and its view
  // writer, so a clock names the process: the UAV latches its gateways by
  // it (core::LockstepFollower).
  if (roles_->view_in) {
    const std::size_t held = held_views_.size();
    roles_->view_in->take(held_views_);
    lift_clocks(held_views_, held);
  }
  const std::size_t first = out.size();
  take_from(*transport_, roles_->clock_in, out);
  for (std::size_t i = first; i < out.size(); ++i) {
    if (out[i].participant != 0) out[i].writer = out[i].participant;
  }
  out.insert(out.end(), std::make_move_iterator(view_clocks_.begin()), std::make_move_iterator(view_clocks_.end()));
  view_clocks_.clear();
}
void Bus::take_phase_done(std::vector<core::PhaseDoneMsg>& out) {
  take_from(*transport_, roles_->done_in, out);
  // Those relayed with the states (take_uav_states, which the ground station calls first).
  out.insert(out.end(), std::make_move_iterator(roles_->relayed_reports.begin()),
             std::make_move_iterator(roles_->relayed_reports.end()));
  roles_->relayed_reports.clear();
}
void Bus::take_uav_reports(std::vector<core::PhaseDoneMsg>& out) { take_from(*transport_, roles_->reports_in, out); }
void Bus::take_commands(std::vector<core::CommandMsg>& out) { take_from(*transport_, roles_->command_in, out); }
void Bus::take_scenarios(std::vector<core::ScenarioMsg>& out) { take_from(*transport_, roles_->scenario_in, out); }

void Bus::take_uav_states(std::vector<core::UavStateMsg>& out) {
  if (roles_->home_states_in) {
    roles_->home_states_in->take(out, roles_->departed_uavs);
  } else if (!roles_->ground_states_in) {
    transport_->keep_alive();
  }
  if (roles_->ground_states_in) {
    // Each sample is a batch of one place agent's relays, in the order it
    // relayed them. A relayed departure is a note, not a state
    // (UavStateMsg::departed).
    relayed_batches_.clear();
    roles_->ground_states_in->take(relayed_batches_);
    for (auto& batch : relayed_batches_) {
      // The gateway's reports of its UAVs' phase: taken with the PhaseDone
      // samples (take_phase_done), judged by who relayed them.
      for (auto& r : batch.reports) {
        r.participant = batch.participant;
        roles_->relayed_reports.push_back(std::move(r));
      }
      for (auto& st : batch.uavs) {
        st.participant = batch.participant;  // the relaying place agent's process
        if (st.departed) {
          roles_->relayed_departures.emplace_back(st.uav, st.tick);
          roles_->relayed_departures.back().participant = batch.participant;
        } else {
          out.push_back(std::move(st));
        }
      }
    }
  }
}

void Bus::take_health(std::vector<core::HealthMsg>& out) {
  if (roles_->health_in) {
    roles_->health_in->take(out, roles_->departed_regions);
  } else {
    transport_->keep_alive();
  }
}

void Bus::take_departed_uavs(std::vector<core::UavDeparture>& out) {
  out.insert(out.end(), roles_->departed_uavs.begin(), roles_->departed_uavs.end());
  roles_->departed_uavs.clear();
  out.insert(out.end(), roles_->relayed_departures.begin(), roles_->relayed_departures.end());
  roles_->relayed_departures.clear();
}

void Bus::take_departed_regions(std::vector<uint32_t>& out) {
  out.insert(out.end(), roles_->departed_regions.begin(), roles_->departed_regions.end());
  roles_->departed_regions.clear();
}

// ------------------------------------------------------- wait, flush, match
namespace {
template <typename Kinds>
std::vector<EndpointId> of_kinds(const std::vector<std::pair<TopicKind, EndpointId>>& endpoints, const Kinds& kinds) {
  std::vector<EndpointId> ids;
  for (const auto& [kind, id] : endpoints) {
    if (std::find(kinds.begin(), kinds.end(), kind) != kinds.end()) ids.push_back(id);
  }
  return ids;
}
}  // namespace

bool Bus::wait(std::initializer_list<TopicKind> kinds, std::chrono::steady_clock::time_point deadline) {
  return transport_->wait(of_kinds(readers_, kinds), deadline);
}

bool Bus::wait_any(std::span<const TopicKind> kinds, std::chrono::steady_clock::time_point deadline) {
  return transport_->wait(of_kinds(readers_, kinds), deadline);
}

namespace {
thread_local uint32_t data_callbacks = 0;  // on_data callbacks under way on this thread (nested: a write delivered)
}  // namespace

bool Bus::in_data_callback() { return data_callbacks > 0; }

bool Bus::on_data(std::span<const TopicKind> kinds, std::function<void()> callback) {
  const std::vector<EndpointId> ids = callback ? of_kinds(readers_, kinds) : std::vector<EndpointId>{};
  if (!callback) return transport_->on_data(ids, {});
  return transport_->on_data(ids, [callback = std::move(callback)] {
    ++data_callbacks;
    struct Leave {
      Leave() = default;
      Leave(const Leave&) = delete;
      Leave& operator=(const Leave&) = delete;
      ~Leave() { --data_callbacks; }
    } leave;
    callback();
  });
}

bool Bus::flush(std::chrono::milliseconds timeout) {
  std::vector<EndpointId> ids;
  for (const auto& [kind, id] : writers_) ids.push_back(id);
  return transport_->flush(ids, timeout);
}

bool Bus::flush(std::initializer_list<TopicKind> kinds, std::chrono::milliseconds timeout) {
  return transport_->flush(of_kinds(writers_, kinds), timeout);
}

uint32_t Bus::matched_deposit_readers(core::RegionId region) const {
  return roles_->deposits.matched(region_partition(region));
}

uint32_t Bus::matched_tile_readers(core::RegionId home) const {
  return roles_->place_fields.matched(tiles_for_partition(home));
}

uint32_t Bus::matched_halo_readers(core::RegionId own, core::RegionId neighbour) const {
  return roles_->halos.matched(halo_partition(own, neighbour));
}

void Bus::offer_halos(std::span<const core::RegionId> neighbours, core::RegionId own) {
  for (core::RegionId n : neighbours) roles_->halos.offer(halo_partition(own, n));
}

void Bus::offer_place_reports() {
  roles_->health.offer(kGroundPartition);
  roles_->fields.offer(kFieldPartition);
  roles_->events.offer(kGroundPartition);
}

void Bus::offer_deposits(std::span<const core::RegionId> regions) {
  for (core::RegionId r : regions) roles_->deposits.offer(region_partition(r));
}

uint32_t Bus::matched_state_readers() {
  if (!roles_->home) return 0;
  return roles_->states.matched(home_partition(*roles_->home));
}

uint32_t Bus::matched_report_readers() {
  if (!roles_->clock_tree) return 0;
  return roles_->phase_done.matched(uav_report_partition(*roles_->home));
}

}  // namespace pheromesh::bus
