// The web console's page (web/index.html, web/style.css and the bundled
// web/src/*.ts), embedded in the program at build time (web/CMakeLists.txt,
// web/embed.cmake), so the ground station serves it without any file on disk.
#pragma once

#include <span>
#include <string_view>

namespace pheromesh::web {

struct Asset {
  std::string_view path;          // e.g. "/index.html"
  std::string_view body;          // the file's bytes
  std::string_view content_type;  // e.g. "text/html; charset=utf-8"
};

// The asset served at `path` (a query string or fragment is ignored);
// "/" maps to "/index.html". nullptr if unknown.
const Asset* find_asset(std::string_view path);

// Every embedded asset, sorted by path.
std::span<const Asset> all_assets();

}  // namespace pheromesh::web
