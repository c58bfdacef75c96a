// Semantic checks of samples received from the network. They must accept any
// field values without crashing: every index is range-checked before use.
#include "pheromesh/core/messages.hpp"

#include <algorithm>
#include <cmath>

#include "pheromesh/core/heading.hpp"
#include "pheromesh/core/layers.hpp"

namespace pheromesh::core {

const char* to_string(TargetEventKind k) {
  switch (k) {
    case TargetEventKind::FirstMarked: return "marked";
    case TargetEventKind::RevisitDue: return "due for a revisit";
    case TargetEventKind::Revisited: return "revisited";
  }
  return "unknown";
}


namespace {

constexpr float kMaxDepositAmount = 1e6F;
constexpr uint8_t kRoleCount = 3;     // Role

bool all_finite(const std::vector<float>& v) {
  return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

std::string cell_text(Cell c) { return "(" + std::to_string(c.x) + ", " + std::to_string(c.y) + ")"; }

}  // namespace

std::optional<std::string> check_deposit(const DepositMsg& d, const MapGeometry& geo, RegionId owner, int layers) {
  if (d.kind >= kDepositKindCount) {
    return "unknown deposit kind " + std::to_string(d.kind);
  }
  if (d.layer >= layers) {
    return "unknown layer " + std::to_string(d.layer);
  }
  if (!std::isfinite(d.spread[0]) || !std::isfinite(d.spread[1]) || !std::isfinite(d.spread[2])) {
    return std::string("deposit spread is not finite");
  }
  if (static_cast<DepositKind>(d.kind) == DepositKind::Ellipse &&
      (d.spread[0] < 0.0F || d.spread[2] < 0.0F ||
       double{d.spread[1]} * d.spread[1] > double{d.spread[0]} * d.spread[2] * (1.0 + 1e-6))) {
    return std::string("deposit spread is not a covariance (positive semi-definite)");
  }
  if (!std::isfinite(d.amount)) {
    return std::string("deposit amount is not finite");
  }
  if (d.amount < 0.0F || d.amount > kMaxDepositAmount) {
    return "deposit amount " + std::to_string(d.amount) + " outside [0, 1e6]";
  }
  if (!geo.in_map(d.cell)) {
    return "deposit cell " + cell_text(d.cell) + " outside the map";
  }
  if (owner >= geo.region_count()) {
    return "owner region " + std::to_string(owner) + " does not exist";
  }
  if (d.region != owner) {
    return "deposit for region " + std::to_string(d.region) + " received by region " + std::to_string(owner);
  }
  // Marks land on the cell the UAV sensed, which the owner holds; a path
  // visit is the UAV's own cell, which may lie in a neighbour region within D0.
  const auto kind = static_cast<DepositKind>(d.kind);
  if ((kind == DepositKind::TargetMark || kind == DepositKind::ObstacleMark || kind == DepositKind::LayerAdd ||
       kind == DepositKind::Observation || kind == DepositKind::PointSet) &&
      !geo.region_rect(owner).contains(d.cell)) {
    return "mark cell " + cell_text(d.cell) + " outside region " + std::to_string(owner);
  }
  return std::nullopt;
}

std::optional<std::string> check_tile(const TileMsg& t, const MapGeometry& geo, int layers) {
  if (t.layer >= layers) {
    return "unknown layer " + std::to_string(t.layer);
  }
  if (!geo.valid_tile(t.tile)) {
    return "tile (" + std::to_string(t.tile.tx) + ", " + std::to_string(t.tile.ty) + ") outside the map";
  }
  if (t.values.size() > kMaxTileCells) {
    return "tile has " + std::to_string(t.values.size()) + " values, more than " + std::to_string(kMaxTileCells);
  }
  const Rect r = geo.tile_rect(t.tile);
  if (t.width != r.w || t.height != r.h) {
    return "tile size " + std::to_string(t.width) + "x" + std::to_string(t.height) + " does not match " +
           std::to_string(r.w) + "x" + std::to_string(r.h);
  }
  if (t.values.size() != static_cast<std::size_t>(t.width) * t.height) {
    return "tile has " + std::to_string(t.values.size()) + " values for " + std::to_string(t.width) + "x" +
           std::to_string(t.height) + " cells";
  }
  if (!all_finite(t.values)) {
    return std::string("tile value is not finite");
  }
  return std::nullopt;
}

std::optional<std::string> check_uav_state(const UavStateMsg& s, const MapGeometry& geo) {
  if (!std::isfinite(s.x) || !std::isfinite(s.y) || !std::isfinite(s.vx) || !std::isfinite(s.vy)) {
    return std::string("UAV state has a non-finite position or velocity");
  }
  // Cell centres are integers, so the map spans [-0.5, width - 0.5]; one cell
  // of margin on each side tolerates rounding by the sender.
  if (s.x < -1.0 || s.y < -1.0 || s.x > static_cast<double>(geo.width()) || s.y > static_cast<double>(geo.height())) {
    return "UAV position (" + std::to_string(s.x) + ", " + std::to_string(s.y) + ") outside the map";
  }
  if (s.heading >= kHeadingCount) {
    return "unknown heading " + std::to_string(s.heading);
  }
  if (s.role >= kRoleCount) {
    return "unknown role " + std::to_string(s.role);
  }
  if (s.broadcasts > 1) {
    return "UAV state says it wrote " + std::to_string(s.broadcasts) + " broadcasts in its tick (at most 1)";
  }
  if (s.view.x < 0 || s.view.y < 0 || s.view.x >= geo.width() || s.view.y >= geo.height()) {
    return "UAV view cell (" + std::to_string(s.view.x) + ", " + std::to_string(s.view.y) + ") outside the map";
  }
  return std::nullopt;
}

std::optional<std::string> check_halo(const HaloMsg& h, const MapGeometry& geo) {
  if (h.region >= geo.region_count()) {
    return "halo from unknown region " + std::to_string(h.region);
  }
  if (h.target.size() > kMaxRingCells || h.obstacle.size() > kMaxRingCells) {
    return "halo ring longer than " + std::to_string(kMaxRingCells);
  }
  const std::size_t expected = ring_size(geo.region_rect(h.region));
  const bool empty = h.target.empty() && h.obstacle.empty();
  if (!empty && (h.target.size() != expected || h.obstacle.size() != expected)) {
    return "halo ring sizes " + std::to_string(h.target.size()) + "/" + std::to_string(h.obstacle.size()) +
           " do not match " + std::to_string(expected);
  }
  if (!all_finite(h.target) || !all_finite(h.obstacle)) {
    return std::string("halo value is not finite");
  }
  return std::nullopt;
}

std::optional<std::string> check_broadcast(const BroadcastMsg& b) {
  if (b.kind >= kBroadcastKindCount) {
    return "unknown broadcast kind " + std::to_string(b.kind);
  }
  if (b.values.size() > kMaxBroadcastValues) {
    return "broadcast has " + std::to_string(b.values.size()) + " values, more than " +
           std::to_string(kMaxBroadcastValues);
  }
  if (!std::all_of(b.values.begin(), b.values.end(), [](double x) { return std::isfinite(x); })) {
    return std::string("broadcast value is not finite");
  }
  return std::nullopt;
}

std::size_t payload_bytes(const TileMsg& m) { return sizeof(m) + m.values.size() * sizeof(float); }

std::size_t payload_bytes(const ViewMsg& m) {
  std::size_t n = sizeof(m) + m.uavs.size() * sizeof(UavStateMsg);
  for (const auto& t : m.tiles) n += payload_bytes(t);
  return n;
}

std::size_t payload_bytes(const FieldMsg& m) {
  std::size_t n = sizeof(m) + m.uavs.size() * sizeof(UavStateMsg);
  for (const auto& t : m.tiles) n += payload_bytes(t);
  for (const auto& r : m.reports) n += payload_bytes(r);
  return n;
}

std::size_t payload_bytes(const HaloMsg& m) {
  return sizeof(m) + (m.target.size() + m.obstacle.size()) * sizeof(float);
}

std::size_t payload_bytes(const BroadcastMsg& m) { return sizeof(m) + m.values.size() * sizeof(double); }

std::size_t payload_bytes(const ClockMsg& m) {
  return sizeof(m) + m.occupancy.size() * sizeof(TileCount) +
         (m.deposits.size() + m.states.size()) * sizeof(RegionCount) + m.absent.size() * sizeof(RegionId);
}

std::size_t payload_bytes(const PhaseDoneMsg& m) { return sizeof(m) + m.deposits.size() * sizeof(RegionCount); }

std::size_t payload_bytes(const ScenarioMsg& m) { return sizeof(m) + m.text.size(); }

std::size_t payload_bytes(const UavStateMsg& m) { return sizeof(m) + m.deposits.size() * sizeof(DepositMsg); }

std::size_t payload_bytes(const DepositBatchMsg& m) { return sizeof(m) + m.deposits.size() * sizeof(DepositMsg); }

std::vector<DepositBatchMsg> deposit_batches(RegionId forwarder, uint32_t tick, std::span<const DepositMsg> deposits) {
  std::vector<DepositBatchMsg> out;
  for (std::size_t next = 0; next < deposits.size(); next += kMaxForwardDeposits) {
    const std::size_t n = std::min(kMaxForwardDeposits, deposits.size() - next);
    out.push_back({forwarder,
                   tick,
                   {deposits.begin() + static_cast<std::ptrdiff_t>(next),
                    deposits.begin() + static_cast<std::ptrdiff_t>(next + n)}});
  }
  return out;
}

std::vector<UavStateMsg> uplink_samples(const UavStateMsg& s, const std::vector<DepositMsg>& deposits) {
  std::vector<UavStateMsg> out;
  std::size_t next = 0;
  do {
    const std::size_t n = std::min(kMaxUplinkDeposits, deposits.size() - next);
    UavStateMsg& sample = out.emplace_back(s);
    sample.deposits.assign(deposits.begin() + static_cast<std::ptrdiff_t>(next),
                           deposits.begin() + static_cast<std::ptrdiff_t>(next + n));
    next += n;
  } while (next < deposits.size());
  return out;
}

}  // namespace pheromesh::core
