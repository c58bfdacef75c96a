#include "pheromesh/core/simulator.hpp"

namespace pheromesh::core {

Simulator::Simulator(ScenarioConfig scenario)
    : scenario_(std::move(scenario)),
      geo_(scenario_.geometry()),
      world_(geo_, scenario_.obstacles, scenario_.targets),
      recorder_(scenario_, world_) {
  for (uint32_t i = 0; i < scenario_.uavs; ++i) uavs_.push_back(std::make_unique<UavCore>(scenario_, world_, i));
  for (RegionId r = 0; r < geo_.region_count(); ++r) places_.push_back(std::make_unique<PlaceCore>(scenario_, r));
  deposits_sent_.assign(uavs_.size(), 0);
  tile_samples_.assign(uavs_.size(), 0);
  inbox_.resize(places_.size());
}

void Simulator::step(uint32_t tick) {
  // UAV phase: every UAV sees the tiles of its neighbourhood as the place
  // agents published them at the end of tick k-1 (nothing at tick 0, as no
  // place agent has ticked yet).
  // The same holds for the states of the UAVs over those tiles and for the
  // broadcasts: those of tick k-1.
  UavCore::Output out;
  std::vector<UavStateMsg> states;
  std::vector<BroadcastMsg> broadcasts;
  for (std::size_t i = 0; i < uavs_.size(); ++i) {
    UavCore& u = *uavs_[i];
    if (tick > 0) {
      for (const TileCoord& t : u.neighbourhood()) {
        auto it = tiles_.find({t.tx, t.ty});
        if (it != tiles_.end()) {
          for (const TileMsg& m : it->second) u.receive_tile(m);
          tile_samples_[i] += it->second.size();
        }
        auto st = states_by_tile_.find({t.tx, t.ty});
        if (st != states_by_tile_.end()) {
          for (const UavStateMsg& s : st->second) u.receive_neighbour(s);
        }
      }
      for (const BroadcastMsg& b : broadcasts_) u.receive_broadcast(b);
    }
    u.step(tick, out);
    ++uav_steps_;
    states.push_back(out.state);
    if (out.broadcast) broadcasts.push_back(*out.broadcast);
    for (const DepositMsg& d : out.deposits) inbox_[d.region].push_back(d);
    deposits_sent_[i] += out.deposits.size();
    for (const DetectionMsg& d : out.detections) recorder_.on_detection(d);
    out.state.deposits_sent = deposits_sent_[i];
    out.state.tile_samples_received = tile_samples_[i];
    recorder_.on_uav_state(out.state);
  }
  states_by_tile_.clear();
  for (const UavStateMsg& s : states) {
    const TileCoord t = geo_.tile_of(state_cell(s));
    states_by_tile_[{t.tx, t.ty}].push_back(s);
  }
  broadcasts_ = std::move(broadcasts);
  // Place phase: deposits of tick k, rings of tick k, update, tiles of tick k.
  std::vector<TargetEventMsg> events;
  std::vector<HaloMsg> rings;
  rings.reserve(places_.size());
  for (std::size_t r = 0; r < places_.size(); ++r) {
    const HaloRing ring = places_[r]->begin_tick(inbox_[r], tick, events);
    rings.push_back({static_cast<RegionId>(r), tick, ring.target, ring.obstacle});
    inbox_[r].clear();
  }
  for (auto& p : places_) {
    for (RegionId n : p->neighbours()) p->accept_halo(rings[n]);
    p->finish_tick();
  }
  for (const auto& e : events) recorder_.on_target_event(e);
  std::vector<TileMsg> tiles;
  for (auto& p : places_) p->tiles(tick, false, tiles);
  tiles_.clear();
  for (auto& t : tiles) tiles_[{t.tile.tx, t.tile.ty}].push_back(std::move(t));
  if (tick % 10 == 0) recorder_.sample_coverage();
}

void Simulator::run(const std::function<void(uint32_t)>& on_tick) {
  for (uint32_t k = 0; k <= scenario_.ticks; ++k) {
    step(k);
    if (on_tick) on_tick(k);
  }
  // The final accounting, as the place agents' last health records carry it.
  for (const auto& p : places_) {
    const auto& l = p->ledger();
    recorder_.on_health({p->region(), scenario_.ticks, 0.0F, l.received, l.applied, l.rejected(), 0, true});
  }
  for (std::size_t i = 0; i < uavs_.size(); ++i) {
    UavStateMsg s = uavs_[i]->last_state();
    s.tick = scenario_.ticks;
    s.deposits_sent = deposits_sent_[i];
    s.tile_samples_received = tile_samples_[i];
    s.finished = true;
    recorder_.on_uav_state(s);
  }
  recorder_.sample_coverage();
  recorder_.set_field_summary(field_summary(scenario_, [this](int layer, Cell c) { return field_value(layer, c); }));
}

float Simulator::field_value(int layer, Cell c) const { return places_[geo_.region_of(c)]->value(layer, c); }

int Simulator::layer_count() const { return places_.front()->layer_count(); }

}  // namespace pheromesh::core
