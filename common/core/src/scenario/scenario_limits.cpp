// Scenario limits and the cost model behind them (scenario_limits.hpp).
#include "pheromesh/core/scenario_limits.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>

namespace pheromesh::core {
namespace {

constexpr double kMiB = 1024.0 * 1024.0;

// Resident memory per process, fitted to `pheromesh run` (Cyclone DDS,
// realtime, 2 UAVs, Shao search, 50 ticks, max RSS from metrics.json) on
// 256 x 256 / 1 region, 1024 x 1024 / 1 region and 1024 x 1024 / 4 x 4
// regions (docs/scenario-format.md, "Limits"):
//   place agent  32.7 / 163.1 / 102.0 MiB  -> 24 MiB + 65 B per own cell + 74 B per map cell
//   ground       29.8 /  89.6 /  75.3 MiB  -> 26 MiB + 64 B per map cell
//   UAV          22.0 /  26.2 /  27.8 MiB  -> 22 MiB +  5 B per map cell
// The per-map-cell share of a place agent is the tile cache of the whole
// field it keeps for halos and views; it is why more regions do not shrink a
// place agent below ~74 B per map cell.
constexpr double kUavBaseMib = 22.0, kUavBytesPerMapCell = 5.0;
constexpr double kPlaceBaseMib = 24.0, kPlaceBytesPerOwnCell = 65.0, kPlaceBytesPerMapCell = 74.0;
constexpr double kGroundBaseMib = 26.0, kGroundBytesPerMapCell = 64.0;
// The libraries every process maps (DDS, C++ runtime, ...): in each one's
// RSS, in the machine's memory once. Measured in a swarm of 2000 UAVs
// (`pheromesh bench scale scenarios/scale-100x100.textproto --sizes 2000
// --ticks 600`: RSS - PSS of a UAV 20.6 MiB, a place agent 20.6, the ground
// station 18.3); the swarm total takes less, so it still errs high.
constexpr double kSharedLibrariesMib = 16.0;

std::string num(int64_t v) { return std::to_string(v); }
std::string mib(double v) { return std::to_string(static_cast<int64_t>(std::ceil(v))) + " MiB"; }

Result<bool> read_limit(const char* name, int64_t& out) {
  const char* v = std::getenv(name);
  if (v == nullptr || *v == '\0') return true;
  char* end = nullptr;
  errno = 0;
  const long long x = std::strtoll(v, &end, 10);
  if (errno != 0 || end == v || *end != '\0' || x <= 0) {
    return Error{std::string("$") + name + " = '" + v + "': must be a positive integer"};
  }
  out = x;
  return true;
}

int64_t ceil_div(int64_t a, int64_t b) { return b <= 0 ? 0 : (a + b - 1) / b; }

}  // namespace

Result<ScenarioLimits> ScenarioLimits::from_environment() {
  ScenarioLimits l;
  for (const auto& [name, field] : {std::pair{kMaxMapCellsEnv, &l.max_map_cells}, std::pair{kMaxRegionsEnv, &l.max_regions},
                                    std::pair{kMaxProcessesEnv, &l.max_processes},
                                    std::pair{kMaxProcessMibEnv, &l.max_process_mib},
                                    std::pair{kMaxSwarmMibEnv, &l.max_swarm_mib}}) {
    if (auto r = read_limit(name, *field); !r) return r.error();
  }
  return l;
}

double ScenarioCost::largest_mib() const { return std::max({uav_mib, place_mib, ground_mib}); }

const char* ScenarioCost::largest_role() const {
  if (ground_mib >= place_mib && ground_mib >= uav_mib) return "ground station";
  return place_mib >= uav_mib ? "place agent" : "UAV";
}

ScenarioCost estimate_cost(const ScenarioConfig& s) {
  ScenarioCost c;
  const int64_t w = std::max<int64_t>(s.width, 0), h = std::max<int64_t>(s.height, 0);
  const int64_t rx = std::max<int64_t>(s.regions_x, 1), ry = std::max<int64_t>(s.regions_y, 1);
  const int64_t ts = std::max<int64_t>(s.tile_size, 1);
  c.map_cells = w * h;
  c.regions = rx * ry;
  c.processes = int64_t{s.uavs} + c.regions * (s.standby ? 2 : 1) + 1;
  // The largest region: regions split the tiles as evenly as integers allow
  // (grid.hpp), so none has more than ceil(tiles / regions) tiles a side.
  const int64_t region_w = std::min(w, ceil_div(ceil_div(w, ts), rx) * ts);
  const int64_t region_h = std::min(h, ceil_div(ceil_div(h, ts), ry) * ts);
  const auto map_cells = static_cast<double>(c.map_cells);
  c.uav_mib = kUavBaseMib + kUavBytesPerMapCell * map_cells / kMiB;
  c.place_mib = kPlaceBaseMib + (kPlaceBytesPerOwnCell * static_cast<double>(region_w * region_h) +
                                 kPlaceBytesPerMapCell * map_cells) / kMiB;
  c.ground_mib = kGroundBaseMib + kGroundBytesPerMapCell * map_cells / kMiB;
  // Every place agent is costed as the largest: an upper bound within one
  // tile row/column. The shared libraries count once, not once per process.
  c.swarm_mib = static_cast<double>(s.uavs) * c.uav_mib +
                static_cast<double>(c.regions * (s.standby ? 2 : 1)) * c.place_mib + c.ground_mib -
                static_cast<double>(c.processes - 1) * kSharedLibrariesMib;
  return c;
}

std::vector<LimitViolation> limit_violations(const ScenarioConfig& s, const ScenarioLimits& limits) {
  std::vector<LimitViolation> out;
  const ScenarioCost c = estimate_cost(s);
  if (c.map_cells > limits.max_map_cells) {
    out.push_back({LimitKind::MapCells, "the map has " + num(s.width) + " x " + num(s.height) + " = " + num(c.map_cells) +
                                            " cells, more than the limit of " + num(limits.max_map_cells) +
                                            " cells; set $" + kMaxMapCellsEnv + " to raise it"});
  }
  if (c.regions > limits.max_regions) {
    out.push_back({LimitKind::Regions, "regions_x x regions_y = " + num(s.regions_x) + " x " + num(s.regions_y) + " = " +
                                           num(c.regions) + " place agents, more than the limit of " +
                                           num(limits.max_regions) + "; set $" + kMaxRegionsEnv + " to raise it"});
  }
  if (c.processes > limits.max_processes) {
    out.push_back({LimitKind::Processes,
                   "the swarm needs " + num(c.processes) + " processes (" + num(s.uavs) + " UAVs + " + num(c.regions) +
                       " place agents" + (s.standby ? " x 2 for standbys" : "") +
                       " + 1 ground station), more than the limit of " + num(limits.max_processes) + "; set $" +
                       kMaxProcessesEnv + " to raise it"});
  }
  // Memory is only worth reporting for a map that passed its own limit: a
  // 100000-cell-wide map is one mistake, not three.
  if (c.map_cells <= limits.max_map_cells && c.largest_mib() > static_cast<double>(limits.max_process_mib)) {
    out.push_back({LimitKind::ProcessMemory,
                   std::string("the ") + c.largest_role() + " would need about " + mib(c.largest_mib()) +
                       " (estimated resident memory), more than the limit of " + num(limits.max_process_mib) +
                       " MiB per process; use more regions or a smaller map, or set $" + kMaxProcessMibEnv +
                       " to raise it"});
  }
  if (c.map_cells <= limits.max_map_cells && c.swarm_mib > static_cast<double>(limits.max_swarm_mib)) {
    out.push_back(
        {LimitKind::SwarmMemory, "the swarm's " + num(c.processes) + " processes would need about " + mib(c.swarm_mib) +
                                     " together (estimated memory, shared libraries once), more than the limit of " +
                                     num(limits.max_swarm_mib) + " MiB; set $" + kMaxSwarmMibEnv + " to raise it"});
  }
  return out;
}

Result<bool> check_limits(const ScenarioConfig& s, const ScenarioLimits& limits, const std::string& source) {
  const auto v = limit_violations(s, limits);
  if (v.empty()) return true;
  std::string msg;
  for (const auto& x : v) msg += (msg.empty() ? "" : "\n") + source + ": " + x.what;
  return Error{msg};
}

bool valid_utf8(std::string_view s, std::size_t* bad_offset) {
  std::size_t i = 0;
  const auto fail = [&](std::size_t at) {
    if (bad_offset != nullptr) *bad_offset = at;
    return false;
  };
  while (i < s.size()) {
    const auto b = static_cast<unsigned char>(s[i]);
    if (b < 0x80) {
      ++i;
      continue;
    }
    std::size_t len = 0;
    uint32_t cp = 0;
    if (b >= 0xC2 && b <= 0xDF) {
      len = 2;
      cp = b & 0x1FU;
    } else if (b >= 0xE0 && b <= 0xEF) {
      len = 3;
      cp = b & 0x0FU;
    } else if (b >= 0xF0 && b <= 0xF4) {
      len = 4;
      cp = b & 0x07U;
    } else {
      return fail(i);  // continuation byte, overlong lead (C0, C1) or beyond U+10FFFF (F5..FF)
    }
    if (i + len > s.size()) return fail(i);
    for (std::size_t k = 1; k < len; ++k) {
      const auto c = static_cast<unsigned char>(s[i + k]);
      if ((c & 0xC0U) != 0x80U) return fail(i);
      cp = (cp << 6U) | (c & 0x3FU);
    }
    const bool overlong = (len == 3 && cp < 0x800) || (len == 4 && cp < 0x10000);
    const bool surrogate = cp >= 0xD800 && cp <= 0xDFFF;
    if (overlong || surrogate || cp > 0x10FFFF) return fail(i);
    i += len;
  }
  return true;
}

}  // namespace pheromesh::core
