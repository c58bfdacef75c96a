#include "pheromesh/console/view.hpp"

#include <algorithm>
#include <cmath>

namespace pheromesh::console {

float next_scale(float current, float max_value) {
  if (!(current >= kMinScale)) current = kMinScale;
  if (!std::isfinite(max_value) || max_value <= 0.0F) max_value = 0.0F;
  if (max_value > current) {
    float s = current;
    while (s < max_value && s < 1e30F) s *= 2.0F;
    return s;
  }
  float s = current;
  while (s > kMinScale && max_value < s / 4.0F) s /= 2.0F;
  return std::max(s, kMinScale);
}

void quantise(std::span<const float> values, float scale, std::vector<uint8_t>& out) {
  out.resize(values.size());
  const float k = 255.0F / scale;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const float v = values[i];
    float q = (std::isnan(v) || v <= 0.0F) ? 0.0F : std::min(255.0F, v * k);
    out[i] = static_cast<uint8_t>(std::lround(q));
  }
}

std::string base64(std::span<const uint8_t> b) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((b.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= b.size(); i += 3) {
    const uint32_t n = (uint32_t{b[i]} << 16) | (uint32_t{b[i + 1]} << 8) | b[i + 2];
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += kAlphabet[(n >> 6) & 63];
    out += kAlphabet[n & 63];
  }
  if (const std::size_t rest = b.size() - i; rest > 0) {
    const uint32_t n = (uint32_t{b[i]} << 16) | (rest == 2 ? uint32_t{b[i + 1]} << 8 : 0U);
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += rest == 2 ? kAlphabet[(n >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {
nlohmann::json rect_json(const core::Rect& r) { return {{"x0", r.x0}, {"y0", r.y0}, {"w", r.w}, {"h", r.h}}; }
}  // namespace

nlohmann::json info_json(const ConsoleInfo& info) {
  nlohmann::json regions = nlohmann::json::array();
  for (std::size_t i = 0; i < info.regions.size(); ++i) {
    auto r = rect_json(info.regions[i]);
    r["id"] = i;
    regions.push_back(std::move(r));
  }
  return {{"name", info.scenario_name}, {"path", info.scenario_path}, {"policy", info.policy},
          {"width", info.width}, {"height", info.height}, {"tile_size", info.tile_size},
          {"ticks", info.ticks}, {"tick_rate_hz", info.tick_rate_hz}, {"uavs_expected", info.uavs_expected},
          {"lease_ms", info.lease_ms}, {"sensor_radius", info.sensor_radius}, {"clock", info.clock},
          {"dds", info.dds}, {"layers", info.layers}, {"regions", std::move(regions)}};
}

nlohmann::json frame_json(const ConsoleState& s, const ConsoleInfo& info, uint16_t layer, uint64_t since) {
  const bool full = since == 0 || since > s.version;
  if (full) since = 0;
  nlohmann::json j;
  j["version"] = s.version;
  j["t_s"] = s.t_s;
  j["tick"] = s.tick;
  j["paused"] = s.paused;
  j["full"] = full;
  nlohmann::json lj;
  lj["index"] = layer;
  lj["name"] = layer < info.layers.size() ? info.layers[layer] : std::string();
  nlohmann::json tiles = nlohmann::json::array();
  if (layer < s.layers.size()) {
    const LayerImage& l = s.layers[layer];
    lj["scale"] = l.scale;
    for (const auto& [key, t] : l.tiles) {
      if (t.version <= since) continue;
      tiles.push_back({{"tx", key.first}, {"ty", key.second}, {"x0", t.rect.x0}, {"y0", t.rect.y0}, {"w", t.rect.w},
                       {"h", t.rect.h}, {"tick", t.tick}, {"q", base64(t.q)}});
    }
  } else {
    lj["scale"] = 1.0;
  }
  lj["tiles"] = std::move(tiles);
  j["layer"] = std::move(lj);
  nlohmann::json uavs = nlohmann::json::array();
  for (const auto& [id, u] : s.uavs) {
    nlohmann::json track = nlohmann::json::array();
    for (const auto& p : u.track) {
      if (p.version > since) track.push_back({p.x, p.y});
    }
    uavs.push_back({{"id", id}, {"x", u.x}, {"y", u.y}, {"heading", u.heading}, {"role", u.role}, {"tick", u.tick},
                    {"liveness", to_string(u.liveness)}, {"track", std::move(track)}});
  }
  j["uavs"] = std::move(uavs);
  nlohmann::json regions = nlohmann::json::array();
  for (const auto& r : s.regions) {
    regions.push_back({{"id", r.id}, {"liveness", to_string(r.liveness)}, {"tick", r.tick},
                       {"tick_rate_hz", r.tick_rate_hz}, {"deposits_per_s", r.deposits_per_s},
                       {"deposits_received", r.deposits_received}, {"deposits_applied", r.deposits_applied},
                       {"deposits_rejected", r.deposits_rejected},
                       {"samples_refused", r.samples_refused},
                       {"replica", r.replica},
                       {"replicas_alive", r.replicas_alive}});
  }
  j["regions"] = std::move(regions);
  nlohmann::json targets = nlohmann::json::array();
  for (std::size_t i = 0; i < s.targets.size(); ++i) {
    const auto& t = s.targets[i];
    targets.push_back({{"index", i}, {"x", t.cell.x}, {"y", t.cell.y}, {"status", to_string(t.status)},
                       {"found_by", t.found_by}, {"found_tick", t.found_tick}, {"popup", t.popup}});
  }
  j["targets"] = std::move(targets);
  nlohmann::json obstacles = nlohmann::json::array();
  for (const auto& o : s.obstacles) {
    auto r = rect_json(o.rect);
    r["popup"] = o.popup;
    obstacles.push_back(std::move(r));
  }
  j["obstacles"] = std::move(obstacles);
  nlohmann::json series = nlohmann::json::array();
  for (const auto& p : s.series) {
    if (p.version <= since) continue;
    series.push_back({{"t_s", p.t_s}, {"tick", p.tick}, {"coverage", p.coverage}, {"targets_found", p.targets_found},
                      {"uncertainty", p.uncertainty}});
  }
  j["series"] = std::move(series);
  nlohmann::json commands = nlohmann::json::array();
  for (const auto& c : s.commands) {
    if (c.version <= since) continue;
    commands.push_back({{"t_s", c.t_s}, {"who", c.who}, {"what", c.what}, {"ok", c.ok}, {"result", c.result}});
  }
  j["commands"] = std::move(commands);
  return j;
}

}  // namespace pheromesh::console
