// Scenario loading: protobuf text format -> validated ScenarioConfig.
//
// Two kinds of errors, both as "FILE:LINE:COL: ..." (1-based):
//  - syntax and unknown fields come from protobuf's own text parser, which
//    stops at the first one;
//  - semantic errors are all collected (one line each, sorted by position) and
//    name the field path, e.g. "field 'map.obstacles[2].w': ...". Positions come
//    from the parser's ParseInfoTree; an absent field is reported at the field
//    of the enclosing message (or 1:1 at top level).
#include "pheromesh/core/scenario.hpp"

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <utility>

#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/scenario_limits.hpp"
#include "pheromesh/core/scenario_warnings.hpp"
#include "scenario/field_override.hpp"
#include "scenario/scenario_internal.hpp"
#include "scenario/start_cells_internal.hpp"

namespace pheromesh::core {
namespace scenario_detail {

// Checks a rectangle whose four fields are required; returns it if valid.
std::optional<Rect> check_rect(Validator& v, const Node& n, const pb::Rect& r, std::optional<MapSize> map) {
  bool ok = true;
  using Presence = std::pair<bool, const char*>;
  for (const auto& [has, name] : {Presence{r.has_x(), "x"}, Presence{r.has_y(), "y"}, Presence{r.has_w(), "w"}, Presence{r.has_h(), "h"}}) {
    if (!has) {
      v.required(n, name);
      ok = false;
    }
  }
  if (!ok) return std::nullopt;
  ok = v.int_between(n, "w", r.w(), 1, kMaxMapSide) && ok;
  ok = v.int_between(n, "h", r.h(), 1, kMaxMapSide) && ok;
  if (map) {
    // Report the corner first, then the extent, so one mistake gives one error.
    const bool x_ok = v.int_between(n, "x", r.x(), 0, map->width - 1, "the cell must be inside the map");
    const bool y_ok = v.int_between(n, "y", r.y(), 0, map->height - 1, "the cell must be inside the map");
    if (x_ok && r.w() >= 1 && int64_t{r.x()} + r.w() > map->width) {
      v.fail(n, "w", "extends past the map: x + w = " + format_number(int64_t{r.x()} + r.w()) + " > width " + format_number(int64_t{map->width}));
      ok = false;
    }
    if (y_ok && r.h() >= 1 && int64_t{r.y()} + r.h() > map->height) {
      v.fail(n, "h", "extends past the map: y + h = " + format_number(int64_t{r.y()} + r.h()) + " > height " + format_number(int64_t{map->height}));
      ok = false;
    }
    ok = ok && x_ok && y_ok;
  } else {
    ok = false;  // cannot be placed without a valid map
  }
  if (!ok) return std::nullopt;
  return Rect{r.x(), r.y(), r.w(), r.h()};
}

std::optional<Cell> check_cell(Validator& v, const Node& n, const pb::Cell& c, std::optional<MapSize> map) {
  bool ok = true;
  if (!c.has_x()) {
    v.required(n, "x");
    ok = false;
  }
  if (!c.has_y()) {
    v.required(n, "y");
    ok = false;
  }
  if (!ok || !map) return std::nullopt;
  ok = v.int_between(n, "x", c.x(), 0, map->width - 1, "the cell must be inside the map") && ok;
  ok = v.int_between(n, "y", c.y(), 0, map->height - 1, "the cell must be inside the map") && ok;
  if (!ok) return std::nullopt;
  return Cell{c.x(), c.y()};
}

// The fields outside `policy` that rooms own (Shao: `shao { layers aco }`),
// each room's once, in the order of the policy table: every scenario's,
// whatever its policy, so that a file is checked whole.
void build_room_fields(const pb::Scenario& msg, const Node& root, Validator& v, ScenarioConfig& cfg) {
  std::vector<decltype(PolicyEntry::parse_scenario_fields)> done;
  for (const PolicyEntry* e : policy_table()) {
    const auto parse = e->parse_scenario_fields;
    if (parse == nullptr || std::find(done.begin(), done.end(), parse) != done.end()) continue;
    done.push_back(parse);
    parse(msg, root, v, cfg);
  }
}

// scenario.policy: which policy (the oneof member's entry in the policy
// table), and its parameters (the entry's parser).
void build_policy(const pb::Scenario& msg, const Node& root, Validator& v, ScenarioConfig& cfg,
                  const PluginSite* site) {
  if (!msg.has_policy()) return;  // kDefaultPolicy, without a config
  const pb::Policy& p = msg.policy();
  const FieldDescriptor* member =
      p.GetReflection()->GetOneofFieldDescriptor(p, pb::Policy::descriptor()->oneof_decl(0));
  if (member == nullptr) return;  // `policy {}`: the default as well
  const Node pn = root.child("policy");
  if (p.has_plugin()) {
    build_plugin_policy(p.plugin(), pn.child("plugin"), v, cfg, site);
    return;
  }
  if (p.has_python()) {
    build_python_policy(p.python(), pn.child("python"), v, cfg, site);
    return;
  }
  const PolicyEntry* entry = find_policy(member->name());
  if (entry == nullptr) {
    v.fail(pn, member->name().c_str(),
           "is a policy of scenario.proto without an entry in the policy table (core/src/policy/policy_table.cpp: " +
               policy_names() + ")");
    return;
  }
  cfg.policy = std::string(entry->name);
  entry->parse(p.GetReflection()->GetMessage(p, member), pn.child(member->name().c_str()), v, cfg);
}

// scenario.geo: where the map lies on the Earth (geodetic.hpp).
void build_geo(const pb::Scenario& msg, const Node& root, Validator& v, ScenarioConfig& cfg) {
  if (!msg.has_geo()) return;
  const pb::Geo& g = msg.geo();
  const Node gn = root.child("geo");
  GeoFrame& f = cfg.geo;
  if (g.has_origin_lat_deg()) f.origin_lat_deg = g.origin_lat_deg();
  if (g.has_origin_lon_deg()) f.origin_lon_deg = g.origin_lon_deg();
  if (g.has_origin_alt_m()) f.origin_alt_m = g.origin_alt_m();
  if (g.has_cell_size_m()) f.cell_size_m = g.cell_size_m();
  if (g.has_flight_height_m()) f.flight_height_m = g.flight_height_m();
  v.real_in(gn, "origin_lat_deg", f.origin_lat_deg, -kGeoMaxAbsLatDeg, false, kGeoMaxAbsLatDeg, false);
  v.real_in(gn, "origin_lon_deg", f.origin_lon_deg, -180.0, false, 180.0, false);
  v.real_in(gn, "origin_alt_m", f.origin_alt_m, kGeoMinAltM, false, kGeoMaxAltM, false);
  v.real_in(gn, "cell_size_m", f.cell_size_m, 0.0, true, kGeoMaxCellSizeM, false);
  v.real_in(gn, "flight_height_m", f.flight_height_m, 0.0, false, kGeoMaxFlightHeightM, false);
}

// scenario.fault: one fault schedule line each (faults.hpp), one clock for
// all. UAV indices are checked by `pheromesh run`, which may change the
// swarm's size; regions are the map's.
void build_faults(const pb::Scenario& msg, const Node& root, Validator& v, ScenarioConfig& cfg) {
  // parse_fault_schedule prefixes its errors with their source; the
  // validator's prefix (file, line, field) replaces it.
  constexpr std::string_view kSource = "fault";
  const std::string source_prefix = std::string(kSource) + ": ";
  std::optional<bool> in_ticks;
  const uint32_t regions = static_cast<uint32_t>(std::max(cfg.regions_x, 1) * std::max(cfg.regions_y, 1));
  for (int i = 0; i < msg.fault_size(); ++i) {
    auto s = parse_fault_schedule(msg.fault(i), std::string(kSource));
    if (!s) {
      std::string what = s.error().message;
      if (what.rfind(source_prefix, 0) == 0) what.erase(0, source_prefix.size());
      v.fail(root, "fault", what, i);
      continue;
    }
    bool ok = true;
    for (const auto& e : s->events) {
      if (in_ticks && *in_ticks != e.at_tick.has_value()) {
        v.fail(root, "fault",
               "'" + e.text +
                   "': mixes tick times (t) with wall times (s, ms) of the lines above; "
                   "use one clock",
               i);
        ok = false;
        break;
      }
      in_ticks = e.at_tick.has_value();
      for (const auto& t : e.targets) {
        if (t.role == "place" && t.index >= regions) {
          const std::string have = regions == 1
                                       ? "1 region: place:0"
                                       : std::to_string(regions) + " regions: place:0-" + std::to_string(regions - 1);
          v.fail(root, "fault", "'" + e.text + "': " + t.process_name() + " does not exist (the map has " + have + ")",
                 i);
          ok = false;
          break;
        }
      }
      if (!ok) break;
    }
    if (ok) merge_fault_schedules(cfg.faults, s.value());
  }
}

// Every string of the scenario (its name, fault lines, policy choices) may end
// up in JSON, in recordings and on the web console; one that is not UTF-8
// made nlohmann::json throw at the end of a run and left a 0-byte
// metrics.json. Refused here, at its line, without echoing the bad bytes.
void check_utf8(const Message& msg, const Node& n, Validator& v) {
  const auto* refl = msg.GetReflection();
  std::vector<const FieldDescriptor*> fields;
  refl->ListFields(msg, &fields);
  const auto complain = [&](const FieldDescriptor* fd, const std::string& value, int index) {
    std::size_t at = 0;
    if (valid_utf8(value, &at)) return;
    v.fail(n, fd->name().c_str(),
           "is not valid UTF-8 (byte " + std::to_string(at + 1) + " of " + std::to_string(value.size()) +
               "); strings of a scenario end up in JSON output and must be UTF-8",
           index);
  };
  for (const FieldDescriptor* fd : fields) {
    if (fd->cpp_type() == FieldDescriptor::CPPTYPE_STRING) {
      if (fd->is_repeated()) {
        for (int i = 0; i < refl->FieldSize(msg, fd); ++i) complain(fd, refl->GetRepeatedString(msg, fd, i), i);
      } else {
        complain(fd, refl->GetString(msg, fd), -1);
      }
    } else if (fd->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
      if (fd->is_repeated()) {
        for (int i = 0; i < refl->FieldSize(msg, fd); ++i) {
          check_utf8(refl->GetRepeatedMessage(msg, fd, i), n.child(fd->name().c_str(), i), v);
        }
      } else {
        check_utf8(refl->GetMessage(msg, fd), n.child(fd->name().c_str()), v);
      }
    }
  }
}

// The limits of scenario_limits.hpp, each reported at the field that asks for it.
void check_scenario_limits(const Node& root, const ScenarioConfig& cfg, const ScenarioLimits& limits, Validator& v) {
  const Node mn = root.child("map");
  const Node sn = root.child("swarm");
  for (const auto& x : limit_violations(cfg, limits)) {
    switch (x.kind) {
      case LimitKind::MapCells:
      case LimitKind::ProcessMemory:
        v.fail(mn, "width", x.what);
        break;
      case LimitKind::Regions:
        v.fail(mn, "regions_x", x.what);
        break;
      case LimitKind::Processes:
      case LimitKind::SwarmMemory:
        v.fail(sn, "uavs", x.what);
        break;
    }
  }
}

namespace {

// map.width and map.height; the map's size when both are valid.
std::optional<MapSize> build_map_size(const pb::Scenario& msg, const Node& mn, Validator& v, ScenarioConfig& cfg) {
  const pb::Map& m = msg.map();
  bool size_ok = true;
  if (!m.has_width()) {
    if (msg.has_map()) v.required(mn, "width");
    size_ok = false;
  } else {
    size_ok = v.int_between(mn, "width", m.width(), kMinMapSide, kMaxMapSide) && size_ok;
    cfg.width = m.width();
  }
  if (!m.has_height()) {
    if (msg.has_map()) v.required(mn, "height");
    size_ok = false;
  } else {
    size_ok = v.int_between(mn, "height", m.height(), kMinMapSide, kMaxMapSide) && size_ok;
    cfg.height = m.height();
  }
  const std::optional<MapSize> map = size_ok ? std::optional<MapSize>(MapSize{cfg.width, cfg.height}) : std::nullopt;
  return map;
}

// Whether map.tile_size and the regions are valid.
struct TilingChecks {
  bool tile_ok = false;
  bool regions_ok = false;
};

TilingChecks build_tiling(const pb::Map& m, const Node& mn, const std::optional<MapSize>& map, Validator& v,
                          ScenarioConfig& cfg) {
  if (m.has_tile_size()) cfg.tile_size = m.tile_size();
  const bool tile_ok = v.int_between(mn, "tile_size", cfg.tile_size, kMinTileSize, kMaxTileSize,
                                     "a tile must fit one DDS sample of <= 1024 cells");
  if (m.has_regions_x()) cfg.regions_x = m.regions_x();
  if (m.has_regions_y()) cfg.regions_y = m.regions_y();
  bool regions_ok = false;
  if (map && tile_ok) {
    const int32_t tiles_x = (cfg.width + cfg.tile_size - 1) / cfg.tile_size;
    const int32_t tiles_y = (cfg.height + cfg.tile_size - 1) / cfg.tile_size;
    regions_ok = v.int_between(mn, "regions_x", cfg.regions_x, 1, tiles_x, "at most one region per tile column (tiles across = ceil(width / tile_size))");
    regions_ok = v.int_between(mn, "regions_y", cfg.regions_y, 1, tiles_y, "at most one region per tile row (tiles down = ceil(height / tile_size))") && regions_ok;
  } else {
    v.int_between(mn, "regions_x", cfg.regions_x, 1, kMaxMapSide);
    v.int_between(mn, "regions_y", cfg.regions_y, 1, kMaxMapSide);
  }
  return {tile_ok, regions_ok};
}

// Valid obstacles with their index, for the checks that depend on them.
std::vector<std::pair<int, Rect>> build_obstacles(const pb::Map& m, const Node& mn, const std::optional<MapSize>& map,
                                                  Validator& v, ScenarioConfig& cfg) {
  std::vector<std::pair<int, Rect>> valid_obstacles;
  for (int i = 0; i < m.obstacles_size(); ++i) {
    const pb::Rect& o = m.obstacles(i);
    cfg.obstacles.push_back(Rect{o.x(), o.y(), o.w(), o.h()});
    if (auto r = check_rect(v, mn.child("obstacles", i), o, map)) valid_obstacles.emplace_back(i, *r);
  }
  return valid_obstacles;
}

void build_targets(const pb::Map& m, const Node& mn, const std::optional<MapSize>& map,
                   const std::vector<std::pair<int, Rect>>& valid_obstacles, Validator& v, ScenarioConfig& cfg) {
  std::vector<std::pair<int, Cell>> valid_targets;
  for (int i = 0; i < m.targets_size(); ++i) {
    const pb::Cell& t = m.targets(i);
    const Node tn = mn.child("targets", i);
    cfg.targets.push_back(Cell{t.x(), t.y()});
    bool ok = true;
    if (!t.has_x()) {
      v.required(tn, "x");
      ok = false;
    }
    if (!t.has_y()) {
      v.required(tn, "y");
      ok = false;
    }
    if (!ok || !map) continue;
    ok = v.int_between(tn, "x", t.x(), 0, map->width - 1, "the cell must be inside the map") && ok;
    ok = v.int_between(tn, "y", t.y(), 0, map->height - 1, "the cell must be inside the map") && ok;
    if (!ok) continue;
    const Cell c{t.x(), t.y()};
    for (const auto& [j, r] : valid_obstacles) {
      if (r.contains(c)) {
        v.fail(mn, "targets", "lies on obstacle map.obstacles[" + std::to_string(j) + "]", i);
        ok = false;
        break;
      }
    }
    for (const auto& [j, other] : valid_targets) {
      if (other == c) {
        v.fail(mn, "targets", "same cell as map.targets[" + std::to_string(j) + "]", i);
        ok = false;
        break;
      }
    }
    if (ok) valid_targets.emplace_back(i, c);
  }
}

// swarm.uavs and swarm.start_area; whether swarm.uavs is valid.
bool build_swarm(const pb::Scenario& msg, const Node& root, const std::string& display_name,
                 const std::optional<MapSize>& map, const std::vector<Rect>& obstacle_rects, Validator& v,
                 ScenarioConfig& cfg) {
  const Node sn = root.child("swarm");
  const pb::Swarm& s = msg.swarm();
  int64_t uavs = cfg.uavs;
  if (s.has_uavs()) uavs = s.uavs();
  bool uavs_ok = v.int_between(sn, "uavs", uavs, 1, kMaxUavs);
  if (uavs_ok && map && uavs > static_cast<int64_t>(kMaxOccupancy) && cfg.tile_size > 0) {
    const int64_t tiles =
        ((map->width + cfg.tile_size - 1) / cfg.tile_size) * int64_t{(map->height + cfg.tile_size - 1) / cfg.tile_size};
    if (tiles > static_cast<int64_t>(kMaxOccupancy)) {
      v.fail(sn, "uavs",
             "more than " + format_number(static_cast<int64_t>(kMaxOccupancy)) + " UAVs (" + format_number(uavs) +
                 ") need a map of at most " + format_number(static_cast<int64_t>(kMaxOccupancy)) +
                 " tiles, this one has " + format_number(tiles) +
                 " (the lockstep clock lists the UAVs over each occupied tile): give fewer UAVs or a larger "
                 "map.tile_size");
      uavs_ok = false;
    }
  }
  if (uavs_ok) cfg.uavs = static_cast<uint32_t>(uavs);
  std::optional<Rect> start;
  const Node an = sn.child("start_area");
  if (s.has_start_area()) {
    const pb::Rect& a = s.start_area();
    cfg.start_area = Rect{a.x(), a.y(), a.w(), a.h()};
    start = check_rect(v, an, a, map);
  } else if (map) {
    cfg.start_area = Rect{0, 0, cfg.width, cfg.height};
    start = cfg.start_area;
  }
  if (start && uavs_ok) {
    const int64_t n_free = free_cells(*start, obstacle_rects);
    if (n_free < uavs && v.overridden("swarm.uavs") && !v.overridden("swarm.start_area")) {
      // The override asked for more UAVs than the file's start area holds:
      // the error names the override.
      v.fail(sn, "uavs",
             "the start area holds " + format_number(n_free) + " UAVs (its free, non-obstacle cells; swarm.start_area at " +
                 display_name + ":" + std::to_string(an.loc().line) + "), fewer than " + format_number(uavs) +
                 ": give at most " + format_number(n_free) + " or a larger swarm.start_area");
    } else if (n_free < uavs) {
      v.fail(an, "has " + format_number(n_free) + " free (non-obstacle) cells, fewer than swarm.uavs = " + format_number(uavs));
    }
  }
  return uavs_ok;
}

void build_run(const pb::Scenario& msg, const Node& root, Validator& v, ScenarioConfig& cfg) {
  const Node rn = root.child("run");
  const pb::Run& run = msg.run();
  if (run.has_ticks() && v.int_between(rn, "ticks", run.ticks(), 1, kMaxU32)) cfg.ticks = static_cast<uint32_t>(run.ticks());
  if (run.has_tick_rate_hz()) cfg.tick_rate_hz = run.tick_rate_hz();
  if (run.has_standby()) cfg.standby = run.standby();
  v.real_in(rn, "tick_rate_hz", cfg.tick_rate_hz, 0.0, true, kMaxTickRateHz, false);
  if (run.has_seed()) cfg.seed = run.seed();
}

}  // namespace

ScenarioConfig build(const pb::Scenario& msg, const TextFormat::ParseInfoTree& tree, const std::string& display_name,
                     const ScenarioLimits& limits, Validator& v, const PluginSite* site) {
  ScenarioConfig cfg;
  const Node root(pb::Scenario::descriptor(), &tree, Loc{1, 1}, "");
  cfg.name = msg.has_name() ? msg.name() : std::filesystem::path(display_name).stem().string();
  if (!msg.has_name() && !valid_utf8(cfg.name)) {
    v.fail(root, "name", "is not set, and the file name is not valid UTF-8 to stand in for it; set name: \"...\"");
  }

  // --- map -------------------------------------------------------------------
  const Node mn = root.child("map");
  const pb::Map& m = msg.map();
  if (!msg.has_map()) v.required(root, "map");
  const std::optional<MapSize> map = build_map_size(msg, mn, v, cfg);
  const TilingChecks tiling = build_tiling(m, mn, map, v, cfg);
  const std::vector<std::pair<int, Rect>> valid_obstacles = build_obstacles(m, mn, map, v, cfg);
  std::vector<Rect> obstacle_rects;
  for (const auto& [i, r] : valid_obstacles) obstacle_rects.push_back(r);
  build_targets(m, mn, map, valid_obstacles, v, cfg);

  // --- swarm -----------------------------------------------------------------
  const bool uavs_ok = build_swarm(msg, root, display_name, map, obstacle_rects, v, cfg);

  // --- run -------------------------------------------------------------------
  build_run(msg, root, v, cfg);

  build_geo(msg, root, v, cfg);
  build_room_fields(msg, root, v, cfg);
  build_policy(msg, root, v, cfg, site);
  build_faults(msg, root, v, cfg);
  if (map && tiling.tile_ok && tiling.regions_ok && uavs_ok) check_scenario_limits(root, cfg, limits, v);
  return cfg;
}

}  // namespace scenario_detail

using scenario_detail::build;
using scenario_detail::CollectingErrorCollector;
using scenario_detail::FieldDescriptor;
using scenario_detail::free_cells;
using scenario_detail::TextFormat;
using scenario_detail::Validator;
namespace pb = scenario_detail::pb;

Result<ScenarioConfig> parse_scenario(std::string_view text, const std::string& display_name) {
  auto limits = ScenarioLimits::from_environment();
  if (!limits) return Error{display_name + ": " + limits.error().message};
  return parse_scenario(text, display_name, limits.value());
}

Result<ScenarioConfig> parse_scenario(std::string_view text, const std::string& display_name,
                                      const ScenarioLimits& limits) {
  return parse_scenario(text, display_name, limits, {});
}

namespace {

// The text of an overridden scenario: what `pheromesh run` hands its
// processes and `patch_scenario` starts from.
std::string overridden_text(pb::Scenario msg, const ScenarioConfig& cfg, const std::string& display_name,
                            const ScenarioOverrides& overrides) {
  // A file without `name:` is named after itself: keep that name when the
  // text moves to another file (OUT/scenario.textproto).
  if (!msg.has_name()) msg.set_name(cfg.name);
  // The processes read this text from another folder (OUT/): the plugin
  // library by the path it was found at.
  if (cfg.plugin && msg.policy().has_plugin()) msg.mutable_policy()->mutable_plugin()->set_library(cfg.plugin->library);
  std::string text = "# " + display_name + " with " + describe_overrides(overrides) + "\n";
  std::string body;
  TextFormat::PrintToString(msg, &body);
  return text + body;
}

}  // namespace

Result<ScenarioConfig> parse_scenario(std::string_view text, const std::string& display_name,
                                      const ScenarioLimits& limits, const ScenarioOverrides& overrides) {
  return scenario_detail::parse_text(text, display_name, limits, overrides, nullptr);
}

namespace {

// The folder a scenario file's relative plugin library is looked for in.
scenario_detail::PluginSite site_of(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path dir = std::filesystem::absolute(std::filesystem::path(path), ec).parent_path();
  return {ec ? std::filesystem::path(path).parent_path().string() : dir.string()};
}

}  // namespace

namespace scenario_detail {

Result<ScenarioConfig> parse_text(std::string_view text, const std::string& display_name, const ScenarioLimits& limits,
                                  const ScenarioOverrides& overrides, const PluginSite* site) {
  pb::Scenario msg;
  TextFormat::ParseInfoTree tree;
  CollectingErrorCollector collector(display_name);
  TextFormat::Parser parser;
  parser.RecordErrorsTo(&collector);
  parser.WriteLocationsTo(&tree);
  if (!parser.ParseFromString(std::string(text), &msg)) {
    std::string out;
    for (const auto& e : collector.errors()) {
      if (!out.empty()) out += '\n';
      out += e;
    }
    if (out.empty()) out = display_name + ": cannot parse scenario";
    return Error{out};
  }
  // The overrides change the parsed message; the positions of what they did
  // not change are still the file's (the ParseInfoTree of its text).
  std::string not_applied;
  std::vector<std::pair<std::string, std::string>> overridden;
  const auto policy_of = [](const pb::Scenario& m) {
    const FieldDescriptor* member =
        m.policy().GetReflection()->GetOneofFieldDescriptor(m.policy(), pb::Policy::descriptor()->oneof_decl(0));
    return member == nullptr ? std::string(kDefaultPolicy) : member->name();
  };
  const std::string policy_before = policy_of(msg);
  for (const auto& o : overrides) {
    auto set = field_override::set_field(msg, o.path, o.value, "the scenario");
    if (!set) {
      not_applied += (not_applied.empty() ? "" : "\n") + o.source + ": " + set.error().message;
      continue;
    }
    // The field setter refuses a second member of the oneof; a file without
    // a policy runs the Shao search, which an override must not switch either.
    if (const auto now = policy_of(msg); now != policy_before) {
      return Error{o.source + ": the scenario's policy is " + policy_before +
                   " (the file chooses none: the default); an override does not switch the policy to " + now +
                   " (change it in the file)"};
    }
    overridden.emplace_back(std::move(set).value(), o.source);
  }
  if (!not_applied.empty()) return Error{not_applied};
  Validator v(display_name);
  v.name_overrides(std::move(overridden));
  // Errors at a line of the file may come from an overridden value (a start
  // area too small for --uavs): say which overrides the scenario had.
  const auto failed = [&] {
    std::string out = v.joined();
    if (!overrides.empty() && v.any_not_by_override()) {
      out += "\n(" + display_name + " as changed by " + describe_overrides(overrides) + ")";
    }
    return Error{out};
  };
  const scenario_detail::Node root(pb::Scenario::descriptor(), &tree, scenario_detail::Loc{1, 1}, "");
  scenario_detail::check_utf8(msg, root, v);
  // The checks below quote strings of the scenario in their messages: not
  // with bytes that are not UTF-8.
  if (!v.empty()) return failed();
  ScenarioConfig cfg = build(msg, tree, display_name, limits, v, site);
  if (!v.empty()) return failed();
  cfg.source_text = overrides.empty() ? std::string(text) : overridden_text(msg, cfg, display_name, overrides);
  cfg.overrides = overrides;
  return cfg;
}

}  // namespace scenario_detail

Result<ScenarioConfig> patch_scenario(const ScenarioConfig& base, std::string_view patch, const std::string& display_name) {
  pb::Scenario msg;
  if (!TextFormat::ParseFromString(base.source_text, &msg)) {
    return Error{display_name + ": the base scenario's text does not parse (was it built in memory?)"};
  }
  CollectingErrorCollector collector(display_name + " (patch)");
  TextFormat::Parser parser;
  parser.RecordErrorsTo(&collector);
  if (!parser.MergeFromString(std::string(patch), &msg)) {
    std::string out;
    for (const auto& e : collector.errors()) out += (out.empty() ? "" : "\n") + e;
    return Error{out.empty() ? display_name + ": cannot parse the patch" : out};
  }
  std::string text;
  TextFormat::PrintToString(msg, &text);
  auto limits = ScenarioLimits::from_environment();
  if (!limits) return Error{display_name + ": " + limits.error().message};
  // A plugin's relative library is looked for beside the base scenario's file.
  const scenario_detail::PluginSite site = site_of(base.source_path);
  auto res = scenario_detail::parse_text(text, display_name, limits.value(), base.overrides,
                                         base.source_path.empty() ? nullptr : &site);
  if (res) res->source_path = base.source_path;
  return res;
}

Result<ScenarioConfig> load_scenario(const std::string& path) { return load_scenario(path, ScenarioOverrides{}); }

Result<ScenarioConfig> load_scenario(const std::string& path, const ScenarioOverrides& overrides) {
  auto limits = ScenarioLimits::from_environment();
  if (!limits) return Error{path + ": " + limits.error().message};
  return load_scenario(path, limits.value(), overrides);
}

Result<ScenarioConfig> load_scenario(const std::string& path, const ScenarioLimits& limits) {
  return load_scenario(path, limits, {});
}

Result<ScenarioConfig> load_scenario(const std::string& path, const ScenarioLimits& limits,
                                     const ScenarioOverrides& overrides) {
  const auto fail = [&path](int err) {
    return Error{path + ": cannot read file: " + std::error_code(err, std::generic_category()).message()};
  };
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) return fail(errno);
  std::string text;
  char buf[8192];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, f.get())) > 0) text.append(buf, n);
  if (std::ferror(f.get()) != 0) return fail(errno != 0 ? errno : EIO);
  const scenario_detail::PluginSite site = site_of(path);
  auto res = scenario_detail::parse_text(text, path, limits, overrides, &site);
  if (res) res->source_path = path;
  return res;
}

Result<ScenarioOverride> parse_override(std::string_view arg, std::string_view flag) {
  const std::size_t eq = arg.find('=');
  if (eq == std::string_view::npos || eq == 0) {
    return Error{std::string(flag) + " " + std::string(arg) +
                 ": expected PATH=VALUE, a field path of the scenario and its value, e.g. " + std::string(flag) +
                 " swarm.uavs=20 or " + std::string(flag) + " shao.aco.alpha=2"};
  }
  return ScenarioOverride{std::string(arg.substr(0, eq)), std::string(arg.substr(eq + 1)),
                          std::string(flag) + " " + std::string(arg)};
}

std::vector<std::string> scenario_warnings(const ScenarioConfig& s) {
  std::vector<std::string> out;
  // The file's own text, for its lines (an overridden scenario's source_text
  // is reprinted).
  std::string text = s.source_text;
  if (!s.source_path.empty()) {
    std::ifstream in(s.source_path, std::ios::binary);
    if (in) text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  pb::Scenario msg;
  TextFormat::ParseInfoTree tree;
  TextFormat::Parser parser;
  CollectingErrorCollector quiet(s.source_path);
  parser.RecordErrorsTo(&quiet);
  parser.WriteLocationsTo(&tree);
  if (!parser.ParseFromString(text, &msg)) return out;
  const std::string display = s.source_path.empty() ? s.name : s.source_path;
  const scenario_detail::Node root(pb::Scenario::descriptor(), &tree, scenario_detail::Loc{1, 1}, "");
  // Blocks outside `policy` that a room reads for its own policies only
  // (PolicyEntry::parse_scenario_fields; today `shao`): beside another
  // policy they change nothing, which the author should know.
  if (msg.has_shao()) {
    const PolicyEntry* entry = find_policy(s.policy);
    if (entry == nullptr || entry->parse_scenario_fields == nullptr) {
      std::string readers;
      for (const PolicyEntry* e : policy_table()) {
        if (e->parse_scenario_fields != nullptr) readers += (readers.empty() ? "" : " and ") + std::string(e->name);
      }
      out.push_back(scenario_detail::prefix(display, root.loc_of("shao")) + "block 'shao': the policy " + s.policy +
                    " does not read it (" + readers + " do); it changes nothing in this run: remove it, or choose "
                    "one of those policies");
    }
  }
  return out;
}

std::string describe_overrides(const ScenarioOverrides& overrides) {
  std::string s;
  for (const auto& o : overrides) s += (s.empty() ? "" : ", ") + o.source;
  return s;
}


}  // namespace pheromesh::core
