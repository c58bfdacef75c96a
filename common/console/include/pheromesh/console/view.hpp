// The console's JSON (docs/console.md) and the 8-bit quantisation of the
// pheromone layers that keeps it small.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "pheromesh/console/state.hpp"

namespace pheromesh::console {

// The scale a layer should use next, given its current scale and the largest
// value now in it: the smallest power of two >= the value when the value
// exceeds the scale; half... a quarter: the scale shrinks only when the value
// falls below a quarter of it (hysteresis, so tiles are not all resent when a
// value wobbles around a power of two). Never below kMinScale.
float next_scale(float current, float max_value);
inline constexpr float kMinScale = 1.0F / 1024.0F;

// q = round(255 * clamp(v / scale, 0, 1)); NaN and negative values -> 0.
void quantise(std::span<const float> values, float scale, std::vector<uint8_t>& out);

std::string base64(std::span<const uint8_t> bytes);

nlohmann::json info_json(const ConsoleInfo& info);
// The answer to GET /api/frame: what changed after `since` (everything when
// since is 0 or newer than the state, i.e. from an earlier console).
nlohmann::json frame_json(const ConsoleState& s, const ConsoleInfo& info, uint16_t layer, uint64_t since);

}  // namespace pheromesh::console
