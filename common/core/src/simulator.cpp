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
  UavCore::Output out;
  for (std::size_t i = 0; i < uavs_.size(); ++i) {
    UavCore& u = *uavs_[i];
    if (tick > 0) {
      for (const TileCoord& t : u.neighbourhood()) {
        auto it = tiles_.find({t.tx, t.ty});
        if (it == tiles_.end()) continue;
        for (const TileMsg& m : it->second) u.receive_tile(m);
        tile_samples_[i] += it->second.size();
      }
    }
    u.step(tick, out);
    ++uav_steps_;
    for (const DepositMsg& d : out.deposits) inbox_[d.region].push_back(d);
    deposits_sent_[i] += out.deposits.size();
    for (const DetectionMsg& d : out.detections) recorder_.on_detection(d);
    out.state.deposits_sent = deposits_sent_[i];
    out.state.tile_samples_received = tile_samples_[i];
    recorder_.on_uav_state(out.state);
  }
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
    UavStateMsg s{};
    s.uav = static_cast<uint32_t>(i);
    s.tick = scenario_.ticks;
    s.x = uavs_[i]->cell().x;
    s.y = uavs_[i]->cell().y;
    s.heading = static_cast<uint8_t>(uavs_[i]->heading());
    s.deposits_sent = deposits_sent_[i];
    s.tile_samples_received = tile_samples_[i];
    s.finished = true;
    recorder_.on_uav_state(s);
  }
  recorder_.sample_coverage();
}

float Simulator::field_value(int layer, Cell c) const {
  return places_[geo_.region_of(c)]->field().value(static_cast<Layer>(layer), c);
}

}  // namespace pheromesh::core
