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

}  // namespace pheromesh::test
