#include "pheromesh/core/intake.hpp"

#include <algorithm>

namespace pheromesh::core {

namespace {
// The first tile with a value outside its layer's range, as a refusal.
template <typename Tiles>
std::optional<std::string> out_of_range(const Tiles& tiles, std::span<const ValueRange> ranges) {
  for (const auto& t : tiles) {
    if (auto reason = check_tile_range(t, ranges)) return reason;
  }
  return std::nullopt;
}
}  // namespace

IntakeVerdict check_view(const ViewMsg& v, uint32_t me, uint32_t ceiling, const IntakeRules& r) {
  if (v.uav != me) return IntakeVerdict::drop("a view addressed to uav " + std::to_string(v.uav));
  if (auto reason = check_tick_reachable(v.tick, ceiling, "view"))
    return IntakeVerdict::refuse(Refusal::TickFarAhead, *reason);
  if (auto reason = out_of_range(v.tiles, r.ranges)) return IntakeVerdict::refuse(Refusal::ValueOutOfRange, *reason);
  return IntakeVerdict::take();
}

IntakeVerdict check_view_tile(const TileMsg& t, const IntakeRules& r) {
  if (auto reason = check_tile(t, r.geo, r.layers)) {
    return IntakeVerdict::drop("tile (" + std::to_string(t.tile.tx) + "," + std::to_string(t.tile.ty) + ") layer " +
                               std::to_string(t.layer) + ": " + *reason);
  }
  return IntakeVerdict::take();
}

IntakeVerdict check_neighbour(const UavStateMsg& s, const IntakeRules& r) {
  if (auto reason = check_uav_state(s, r.geo))
    return IntakeVerdict::drop("state of uav " + std::to_string(s.uav) + ": " + *reason);
  if (auto reason = check_uav_id(s.uav, r.swarm))
    return IntakeVerdict::refuse(Refusal::UnknownUav, "a neighbour's state: " + *reason);
  return IntakeVerdict::take();
}

IntakeVerdict check_broadcast_from(const BroadcastMsg& b, const IntakeRules& r) {
  if (auto reason = check_broadcast(b))
    return IntakeVerdict::drop("broadcast of uav " + std::to_string(b.uav) + ": " + *reason);
  if (auto reason = check_uav_id(b.uav, r.swarm))
    return IntakeVerdict::refuse(Refusal::UnknownUav, "a broadcast: " + *reason);
  return IntakeVerdict::take();
}

IntakeVerdict check_home_state(const UavStateMsg& s, const UavStateMsg* before, Cell start, double max_step,
                               uint32_t ceiling, const IntakeRules& r) {
  if (auto reason = check_uav_id(s.uav, r.swarm))
    return IntakeVerdict::refuse(Refusal::UnknownUav, "a state: " + *reason);
  if (auto reason = check_uav_state(s, r.geo))
    return IntakeVerdict::drop("state of uav " + std::to_string(s.uav) + ": " + *reason);
  if (auto reason = check_tick_reachable(s.tick, ceiling, "state"))
    return IntakeVerdict::refuse(Refusal::TickFarAhead, *reason);
  if (auto reason = check_state_motion(s, before, start, max_step, true)) {
    return IntakeVerdict::refuse(Refusal::ImplausibleState, *reason);
  }
  return IntakeVerdict::take();
}

StateGate::Judged StateGate::judge(const UavStateMsg& s, const UavStateMsg* before, Cell start, double max_step,
                                   uint32_t ceiling, const IntakeRules& r) {
  Judged j{check_home_state(s, before, start, max_step, ceiling, r)};
  // A taken state of a tick before the last accepted one starts a new life
  // (a restarted UAV counts ticks from 0 again): what its earlier life had
  // refused is no answer of this one.
  if (j.verdict.taken() && before != nullptr && s.tick < before->tick) refused_tick_.erase(s.uav);
  if (j.verdict.kind != IntakeVerdict::Kind::Refuse || j.verdict.refusal != Refusal::ImplausibleState) return j;
  j.refused_motion = true;
  auto [it, fresh] = refused_tick_.try_emplace(s.uav, s.tick);
  if (!fresh && s.tick <= it->second) {
    j.copy = true;
  } else {
    it->second = s.tick;
  }
  return j;
}

std::optional<uint32_t> StateGate::refused_tick(uint32_t uav) const {
  auto it = refused_tick_.find(uav);
  if (it == refused_tick_.end()) return std::nullopt;
  return it->second;
}

UavStateMsg refused_answer(const UavStateMsg& s) {
  UavStateMsg a = s;
  a.implausible = true;
  a.deposits.clear();
  return a;
}

IntakeVerdict check_field_chunk(const FieldMsg& f, uint32_t ceiling, const IntakeRules& r) {
  bool ok = f.region < r.geo.region_count();
  for (const auto& t : f.tiles) ok = ok && !check_tile(t, r.geo, r.layers);
  for (const auto& st : f.uavs) ok = ok && !check_uav_state(st, r.geo);
  if (!ok) return IntakeVerdict::drop("a malformed field chunk of region " + std::to_string(f.region));
  if (auto reason = check_tick_reachable(f.tick, ceiling, "field chunk")) {
    return IntakeVerdict::refuse(Refusal::TickFarAhead, *reason);
  }
  if (auto reason = out_of_range(f.tiles, r.ranges)) return IntakeVerdict::refuse(Refusal::ValueOutOfRange, *reason);
  for (const auto& st : f.uavs) {
    if (auto reason = check_uav_id(st.uav, r.swarm)) {
      return IntakeVerdict::refuse(Refusal::UnknownUav, "a field chunk with " + *reason);
    }
  }
  return IntakeVerdict::take();
}

CarriedDeposits carried_deposits(const StateGate::Judged& j) {
  if (j.refused_motion) return CarriedDeposits::Reject;
  return j.verdict.kind == IntakeVerdict::Kind::Refuse ? CarriedDeposits::Refuse : CarriedDeposits::Judge;
}

}  // namespace pheromesh::core
