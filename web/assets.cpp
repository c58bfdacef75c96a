#include "pheromesh/web/assets.hpp"

#include <cstddef>

// Defined in the generated assets_data.cpp (web/embed.cmake).
namespace pheromesh::web::detail {
extern const Asset kAssets[];
extern const std::size_t kAssetCount;
}  // namespace pheromesh::web::detail

namespace pheromesh::web {

std::span<const Asset> all_assets() { return {detail::kAssets, detail::kAssetCount}; }

const Asset* find_asset(std::string_view path) {
  const std::size_t cut = path.find_first_of("?#");
  if (cut != std::string_view::npos) path = path.substr(0, cut);
  if (path.empty() || path == "/") path = "/index.html";
  for (const Asset& a : all_assets()) {
    if (a.path == path) return &a;
  }
  return nullptr;
}

}  // namespace pheromesh::web
