// What several unit test files share: one definition each, which a unity
// build (CMAKE_UNITY_BUILD, the Makefile's default) needs, since it compiles
// several test files as one. A file names the helpers it uses with
// `using test::...;` in its own namespace.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>

#include "pheromesh/core/messages.hpp"

namespace pheromesh::test {

inline constexpr double kEps = 1e-9;
inline constexpr double kPi = std::numbers::pi;

// A file of the source tree, by its path from the top.
inline std::string source_path(const std::string& rel) { return std::string(PHEROMESH_SOURCE_DIR) + "/" + rel; }

// A whole file as bytes ("" if it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Expects a reason that contains `word`.
inline void expect_reason(const std::optional<std::string>& reason, const std::string& word) {
  ASSERT_TRUE(reason.has_value()) << "expected a reason containing '" << word << "'";
  EXPECT_NE(reason->find(word), std::string::npos) << *reason;
}

// A UAV's state at (x, y) of `tick`, its view around that cell.
inline core::UavStateMsg state_at(uint32_t uav, uint32_t tick, double x, double y) {
  core::UavStateMsg s;
  s.uav = uav;
  s.tick = tick;
  s.x = x;
  s.y = y;
  s.view = {static_cast<int32_t>(x), static_cast<int32_t>(y)};
  return s;
}

}  // namespace pheromesh::test
