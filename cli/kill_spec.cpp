#include "kill_spec.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pheromesh::cli {

namespace {
core::Error bad(const std::string& item, const std::string& why) {
  return {"--kill: '" + item + "': " + why + " (expected ROLE:INDEX@TIME, e.g. uav:3@5s or place:0@2500ms)"};
}
}  // namespace

core::Result<std::vector<KillEvent>> parse_kill_spec(const std::string& spec) {
  std::vector<KillEvent> out;
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ',')) {
    item.erase(std::remove_if(item.begin(), item.end(), ::isspace), item.end());
    if (item.empty()) continue;
    const auto colon = item.find(':');
    const auto at = item.find('@');
    if (colon == std::string::npos || at == std::string::npos || at < colon) return bad(item, "malformed");
    KillEvent e;
    e.role = item.substr(0, colon);
    if (e.role != "uav" && e.role != "place") return bad(item, "role must be 'uav' or 'place'");
    const std::string idx = item.substr(colon + 1, at - colon - 1);
    if (idx.empty() || !std::all_of(idx.begin(), idx.end(), ::isdigit) || idx.size() > 6) return bad(item, "bad index");
    e.index = static_cast<uint32_t>(std::stoul(idx));
    std::string t = item.substr(at + 1);
    double scale = 0;
    if (t.size() > 2 && t.ends_with("ms")) {
      scale = 1.0;
      t.resize(t.size() - 2);
    } else if (t.size() > 1 && t.ends_with("s")) {
      scale = 1000.0;
      t.resize(t.size() - 1);
    } else {
      return bad(item, "time needs a unit, s or ms");
    }
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size() || !std::isfinite(v) || v < 0 || v > 86400.0 * 1000) return bad(item, "bad time");
    e.at = std::chrono::milliseconds(static_cast<int64_t>(std::llround(v * scale)));
    out.push_back(e);
  }
  if (out.empty()) return core::Error{"--kill: no events in '" + spec + "'"};
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.at < b.at; });
  return out;
}

}  // namespace pheromesh::cli
