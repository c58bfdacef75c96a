#include "vendor_bus.hpp"

#include "routing.hpp"

namespace pheromesh::bus {

void VendorBus::take_departed_uavs(std::vector<uint32_t>& out) {
  out.insert(out.end(), departed_uavs_.begin(), departed_uavs_.end());
  departed_uavs_.clear();
}

void VendorBus::take_departed_regions(std::vector<core::RegionId>& out) {
  out.insert(out.end(), departed_regions_.begin(), departed_regions_.end());
  departed_regions_.clear();
}

bool VendorBus::refuse(const char* what, std::size_t n) {
  ++stats_.writes_refused;
  log_->warn("refusing to write {} with {} elements: over the IDL bound", what, n);
  return false;
}

std::vector<std::string> VendorBus::tiles_left_behind(const std::string& part) {
  std::vector<std::string> drop;
  for (auto it = left_tiles_.begin(); it != left_tiles_.end();) {
    if (it->first != part && ++it->second > routing::kKeepLeftTileWriter) {
      drop.push_back(it->first);
      it = left_tiles_.erase(it);
    } else {
      ++it;
    }
  }
  left_tiles_[part] = 0;
  return drop;
}

bool VendorBus::keep_alive_due() {
  const auto now = std::chrono::steady_clock::now();
  if (now - last_keep_alive_ < opt_.liveliness_lease / 4) return false;
  last_keep_alive_ = now;
  return true;
}

}  // namespace pheromesh::bus
