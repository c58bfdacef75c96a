// Scenario parsing internals shared by scenario.cpp and the rooms' parsers
// (papers/<paper>/src/scenario.cpp, reached through their PolicyEntry): field
// positions, field paths, validation with "FILE:LINE:COL: field 'a.b': ..."
// messages.
#pragma once

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pheromesh/core/policy_table.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/scenario_limits.hpp"
#include "scenario.pb.h"

namespace pheromesh::core::scenario_detail {

namespace pb = ::pheromesh::scenario;
using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::TextFormat;

constexpr int32_t kMinMapSide = 4;      // [cell]
constexpr int32_t kMaxMapSide = 4096;   // [cell]
constexpr int32_t kMinTileSize = 4;     // [cell]
constexpr int32_t kMaxTileSize = 32;    // [cell]; 32 x 32 = 1024 cells, one DDS sample
// UAV processes of one swarm. Up to 1024 every bound of the IDL holds
// whatever the map; above, a lockstep clock lists the UAVs per occupied
// tile (MAX_OCCUPANCY entries), so the map must have at most that many
// tiles (build_swarm), and a view carries at most MAX_VIEW_UAVS neighbours
// (core::ViewServer::compose keeps the nearest).
constexpr int32_t kMaxUavs = 5000;
constexpr double kMaxTickRateHz = 1000.0;
constexpr double kMaxSensorRadius = 64.0;  // [cell]
constexpr int64_t kMaxU32 = std::numeric_limits<uint32_t>::max();
constexpr double kInf = std::numeric_limits<double>::infinity();

// 1-based position in the text.
struct Loc {
  int line = 1;
  int col = 1;
};

inline std::string format_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return {buf, res.ptr};
}
inline std::string format_number(int64_t v) { return std::to_string(v); }

inline std::string prefix(const std::string& display_name, Loc loc) {
  return display_name + ":" + std::to_string(loc.line) + ":" + std::to_string(loc.col) + ": ";
}

// Collects protobuf's parse errors instead of letting it print them.
class CollectingErrorCollector final : public google::protobuf::io::ErrorCollector {
 public:
  explicit CollectingErrorCollector(const std::string& display_name) : display_name_(display_name) {}
  void AddError(int line, google::protobuf::io::ColumnNumber column, const std::string& message) override {
    if (line < 0) {
      errors_.push_back(display_name_ + ": " + message);
    } else {
      errors_.push_back(prefix(display_name_, {line + 1, column + 1}) + message);
    }
  }
  [[nodiscard]] const std::vector<std::string>& errors() const { return errors_; }

 private:
  const std::string& display_name_;
  std::vector<std::string> errors_;
};

// A message of the parsed text: its descriptor, its ParseInfoTree (null when
// the message was absent from the text), where it stood and its field path.
class Node {
 public:
  Node(const Descriptor* desc, const TextFormat::ParseInfoTree* tree, Loc loc, std::string path)
      : desc_(desc), tree_(tree), loc_(loc), path_(std::move(path)) {}

  [[nodiscard]] Loc loc() const { return loc_; }
  [[nodiscard]] const std::string& path() const { return path_; }

  // Position of `field` (element `index` if repeated); the message's own
  // position when the field is absent.
  [[nodiscard]] Loc loc_of(const char* field, int index = -1) const {
    const FieldDescriptor* fd = desc_->FindFieldByName(field);
    if (tree_ == nullptr || fd == nullptr) return loc_;
    auto p = tree_->GetLocation(fd, fd->is_repeated() ? std::max(index, 0) : -1);
    // List syntax ("targets: [{...}, {...}]") records one location for the
    // whole list: fall back to where the list starts.
    if (p.line < 0 && fd->is_repeated()) p = tree_->GetLocation(fd, 0);
    if (p.line < 0) return loc_;
    return {p.line + 1, p.column + 1};
  }

  [[nodiscard]] std::string path_of(const char* field, int index = -1) const {
    std::string p = path_.empty() ? std::string(field) : path_ + "." + field;
    if (index >= 0) p += "[" + std::to_string(index) + "]";
    return p;
  }

  [[nodiscard]] Node child(const char* field, int index = -1) const {
    const FieldDescriptor* fd = desc_->FindFieldByName(field);
    const TextFormat::ParseInfoTree* nested = nullptr;
    if (tree_ != nullptr && fd != nullptr) nested = tree_->GetTreeForNested(fd, fd->is_repeated() ? std::max(index, 0) : -1);
    return {fd != nullptr ? fd->message_type() : nullptr, nested, loc_of(field, index), path_of(field, index)};
  }

 private:
  const Descriptor* desc_;
  const TextFormat::ParseInfoTree* tree_;
  Loc loc_;
  std::string path_;
};

// Collects semantic errors.
class Validator {
 public:
  explicit Validator(const std::string& display_name) : display_name_(display_name) {}

  // Fields set by overrides (path, source such as "--set swarm.uavs=0"): an
  // error about one names the override, not a line of the file.
  void name_overrides(std::vector<std::pair<std::string, std::string>> overridden) {
    overridden_ = std::move(overridden);
  }

  // Whether an override set the field at `path` or a field inside it.
  [[nodiscard]] bool overridden(const std::string& path) const {
    return std::any_of(overridden_.begin(), overridden_.end(),
                       [&](const auto& o) { return o.first == path || o.first.rfind(path + ".", 0) == 0; });
  }

  void fail_at(Loc loc, const std::string& path, const std::string& what) {
    // The last override of a field is the one in effect.
    for (auto it = overridden_.rbegin(); it != overridden_.rend(); ++it) {
      if (it->first == path) {
        issues_.push_back({Loc{0, 0}, it->second + ": field '" + path + "': " + what});
        ++by_override_;
        return;
      }
    }
    issues_.push_back({loc, prefix(display_name_, loc) + "field '" + path + "': " + what});
  }
  void fail(const Node& n, const char* field, const std::string& what, int index = -1) {
    fail_at(n.loc_of(field, index), n.path_of(field, index), what);
  }
  void fail(const Node& n, const std::string& what) { fail_at(n.loc(), n.path(), what); }

  void required(const Node& n, const char* field) { fail(n, field, "required field is missing"); }

  bool int_between(const Node& n, const char* field, int64_t v, int64_t lo, int64_t hi, const std::string& note = "") {
    if (v >= lo && v <= hi) return true;
    fail(n, field, "must be between " + format_number(lo) + " and " + format_number(hi) + " (got " + format_number(v) + ")" +
                       (note.empty() ? "" : "; " + note));
    return false;
  }

  // Interval check that also rejects nan and +-inf. hi = +inf means unbounded.
  bool real_in(const Node& n, const char* field, double v, double lo, bool lo_open, double hi, bool hi_open) {
    const bool lo_ok = lo_open ? v > lo : v >= lo;
    const bool hi_ok = std::isinf(hi) || (hi_open ? v < hi : v <= hi);
    if (std::isfinite(v) && lo_ok && hi_ok) return true;
    std::string range;
    if (std::isinf(hi)) {
      range = std::string(lo_open ? "> " : ">= ") + format_number(lo);
    } else {
      range = std::string("in ") + (lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) + (hi_open ? ")" : "]");
    }
    fail(n, field, "must be " + (std::isfinite(v) ? range : "a finite number " + range) + " (got " + format_number(v) + ")");
    return false;
  }

  [[nodiscard]] bool empty() const { return issues_.empty(); }
  // Whether an error is about a field no override set (its line is the file's).
  [[nodiscard]] bool any_not_by_override() const { return issues_.size() > by_override_; }
  [[nodiscard]] std::string joined() {
    std::stable_sort(issues_.begin(), issues_.end(), [](const Issue& a, const Issue& b) {
      return a.loc.line != b.loc.line ? a.loc.line < b.loc.line : a.loc.col < b.loc.col;
    });
    std::string out;
    for (const auto& i : issues_) {
      if (!out.empty()) out += '\n';
      out += i.text;
    }
    return out;
  }

 private:
  struct Issue {
    Loc loc;
    std::string text;
  };
  const std::string& display_name_;
  std::vector<Issue> issues_;
  std::vector<std::pair<std::string, std::string>> overridden_;
  std::size_t by_override_ = 0;
};

// Map side lengths once they are known to be valid.
struct MapSize {
  int32_t width;
  int32_t height;
};

// Checks a rectangle whose four fields are required; returns it if valid.
std::optional<Rect> check_rect(Validator& v, const Node& n, const pb::Rect& r, std::optional<MapSize> map);
// Checks a required cell inside the map; returns it if valid.
std::optional<Cell> check_cell(Validator& v, const Node& n, const pb::Cell& c, std::optional<MapSize> map);

// Where a scenario came from, for its plugin (`policy { plugin { ... } }`):
// the folder its relative library is looked for in first. Text without a
// file has none, and loads no plugin (plugin_loader.hpp).
struct PluginSite {
  std::string scenario_dir;
};

// scenario.policy.plugin: resolves, pins and loads the library
// (plugin_loader.hpp) and lets the plugin read its config (plugin_scenario.cpp).
void build_plugin_policy(const pb::PolicyPlugin& msg, const Node& n, Validator& v, ScenarioConfig& cfg,
                         const PluginSite* site);

// scenario.policy.python: hands the block to the Python hook
// (python_policy.hpp), or refuses it in a program without one.
void build_python_policy(const pb::PolicyPython& msg, const Node& n, Validator& v, ScenarioConfig& cfg,
                         const PluginSite* site);

// parse_scenario and load_scenario: `site` null for text without a file.
Result<ScenarioConfig> parse_text(std::string_view text, const std::string& display_name,
                                  const ScenarioLimits& limits, const ScenarioOverrides& overrides,
                                  const PluginSite* site);

// A PolicyEntry's parse hook (policy_table.hpp) from a room's parser of its
// own message type: parse_as<pb::LiuPolicy, &build_liu>. The table dispatches
// by the oneof member's name, so `msg` is an M unless an entry names a member
// whose message is another type: said at the member's line.
template <class M, void (*Build)(const M&, const Node&, Validator&, ScenarioConfig&)>
void parse_as(const Message& msg, const Node& n, Validator& v, ScenarioConfig& cfg) {
  if (msg.GetDescriptor() != M::descriptor()) {
    v.fail(n, "is a " + msg.GetDescriptor()->full_name() + ", but its entry in the policy table reads a " +
                  M::descriptor()->full_name());
    return;
  }
  Build(static_cast<const M&>(msg), n, v, cfg);
}

}  // namespace pheromesh::core::scenario_detail
