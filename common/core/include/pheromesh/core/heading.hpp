// The eight compass headings of a grid step, shared by every policy that
// moves cell by cell (Shao 2020 Sec. 4.2's ACO, Liu 2022's grid steps, the
// Shao 2020 Sec. 5 hand-over to the search).
#pragma once

#include <cstdint>

#include "pheromesh/core/grid.hpp"

namespace pheromesh::core {

// Eight compass headings, counter-clockwise from east, 45° apart.
enum class Heading : uint8_t { E = 0, NE, N, NW, W, SW, S, SE };
inline constexpr int kHeadingCount = 8;  // the values of Heading
// Unit step. N is +y: with rows drawn downwards (docs/scenario-format.md)
// "north" points down the screen; the policy only uses relative turns.
Cell step_of(Heading h);
Heading rotate(Heading h, int eighths);  // +1 = 45° counter-clockwise
double heading_angle(Heading h);         // [rad]

}  // namespace pheromesh::core
