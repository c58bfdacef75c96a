#include "pheromesh/core/heading.hpp"

#include <array>
#include <cstddef>
#include <numbers>

namespace pheromesh::core {

namespace {

constexpr std::array<Cell, kHeadingCount> kSteps{{
    {1, 0},
    {1, 1},
    {0, 1},
    {-1, 1},
    {-1, 0},
    {-1, -1},
    {0, -1},
    {1, -1},
}};

}  // namespace

Cell step_of(Heading h) { return kSteps[static_cast<std::size_t>(h) % kHeadingCount]; }

Heading rotate(Heading h, int eighths) {
  const int v = ((static_cast<int>(h) + eighths) % kHeadingCount + kHeadingCount) % kHeadingCount;
  return static_cast<Heading>(v);
}

double heading_angle(Heading h) { return static_cast<double>(static_cast<int>(h)) * std::numbers::pi / 4.0; }

}  // namespace pheromesh::core
