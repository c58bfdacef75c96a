#include "vendor_bus.hpp"

#include <algorithm>

#include "routing.hpp"

namespace pheromesh::bus {

void VendorBus::take_departed_uavs(std::vector<uint32_t>& out) {
  out.insert(out.end(), departed_uavs_.begin(), departed_uavs_.end());
  departed_uavs_.clear();
}

void VendorBus::take_departed_regions(std::vector<uint32_t>& out) {
  out.insert(out.end(), departed_regions_.begin(), departed_regions_.end());
  departed_regions_.clear();
}

bool VendorBus::refuse(const char* what, std::size_t n) {
  ++stats_.writes_refused;
  log_->warn("refusing to write {} with {} elements: over the IDL bound", what, n);
  return false;
}

namespace {
bool tiles_fit(const std::vector<core::TileMsg>& tiles) {
  return std::all_of(tiles.begin(), tiles.end(), [](const auto& t) { return t.values.size() <= core::kMaxTileCells; });
}
}  // namespace

bool VendorBus::view_fits(const core::ViewMsg& m) {
  if (m.tiles.size() > core::kMaxViewTiles) return refuse("view tiles", m.tiles.size());
  if (m.uavs.size() > core::kMaxViewUavs) return refuse("view states", m.uavs.size());
  if (!tiles_fit(m.tiles)) return refuse("view tile values", core::kMaxTileCells + 1);
  return true;
}

bool VendorBus::field_fits(const core::FieldMsg& m) {
  if (m.tiles.size() > core::kMaxFieldTiles) return refuse("field tiles", m.tiles.size());
  if (m.uavs.size() > core::kMaxFieldUavs) return refuse("field states", m.uavs.size());
  if (!tiles_fit(m.tiles)) return refuse("field tile values", core::kMaxTileCells + 1);
  return true;
}

bool VendorBus::keep_alive_due() {
  const auto now = std::chrono::steady_clock::now();
  if (now - last_keep_alive_ < opt_.liveliness_lease / 4) return false;
  last_keep_alive_ = now;
  return true;
}

}  // namespace pheromesh::bus
