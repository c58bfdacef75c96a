// Small angle helpers shared by the policies.
#pragma once

#include <cmath>
#include <numbers>

namespace pheromesh::core {

inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

// a mapped into [0, 2π).
inline double wrap_two_pi(double a) {
  double w = std::fmod(a, kTwoPi);
  if (w < 0.0) w += kTwoPi;
  return w >= kTwoPi ? 0.0 : w;
}

}  // namespace pheromesh::core
