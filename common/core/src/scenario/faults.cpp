#include "pheromesh/core/faults.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

namespace pheromesh::core {

const char* to_string(FaultAction a) {
  switch (a) {
    case FaultAction::Kill:
      return "kill";
    case FaultAction::Stop:
      return "stop";
    case FaultAction::Restart:
      return "restart";
    case FaultAction::Standby:
      return "standby";
    case FaultAction::Partition:
      return "partition";
    case FaultAction::Loss:
      return "loss";
  }
  return "?";
}

std::string FaultTarget::process_name() const { return role == "ground" ? role : role + "-" + std::to_string(index); }

namespace {

constexpr const char* kGrammar =
    "expected e.g. 'kill uav:3 @5s', 'stop place:1 @10s for 5s', 'restart uav:2 @40t for 1s', "
    "'partition uav:0-4,place:1 @10s for 5s', 'loss 30% @0s for 20s', 'standby place:0 @20s'";
constexpr uint32_t kMaxIndex = 1000000;

std::string trim(std::string s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

bool parse_uint(const std::string& s, uint32_t& out) {
  if (s.empty() || s.size() > 7 || !std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); })) {
    return false;
  }
  out = static_cast<uint32_t>(std::stoul(s));
  return out <= kMaxIndex;
}

// "5s", "2500ms" -> seconds; "40t" -> tick.
std::optional<std::string> parse_time(const std::string& t, std::optional<double>& s, std::optional<uint32_t>& tick) {
  if (t.size() > 1 && t.back() == 't') {
    uint32_t k = 0;
    if (!parse_uint(t.substr(0, t.size() - 1), k)) return "bad tick '" + t + "'";
    tick = k;
    return {};
  }
  double scale = 0;
  std::string num = t;
  if (num.size() > 2 && num.ends_with("ms")) {
    scale = 1e-3;
    num.resize(num.size() - 2);
  } else if (num.size() > 1 && num.back() == 's') {
    scale = 1.0;
    num.pop_back();
  } else {
    return "time '" + t + "' needs a unit: s, ms or t (ticks)";
  }
  char* end = nullptr;
  const double v = std::strtod(num.c_str(), &end);
  if (end != num.c_str() + num.size() || !std::isfinite(v) || v < 0 || v * scale > 86400.0 * 7) {
    return "bad time '" + t + "'";
  }
  s = v * scale;
  return {};
}

std::optional<std::string> parse_duration(const std::string& t, double& out) {
  std::optional<double> s;
  std::optional<uint32_t> tick;
  if (auto e = parse_time(t, s, tick)) return e;
  if (tick) return "a duration is wall time (s or ms), not ticks: '" + t + "'";
  out = *s;
  return {};
}

// "uav:0-4,place:1,ground" -> targets.
std::optional<std::string> parse_targets(const std::string& list, std::vector<FaultTarget>& out) {
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    item = trim(item);
    if (item.empty()) continue;
    if (item == "ground") {
      out.push_back({"ground", 0});
      continue;
    }
    const auto colon = item.find(':');
    if (colon == std::string::npos) return "target '" + item + "' is not uav:I, place:R or ground";
    const std::string role = item.substr(0, colon);
    if (role != "uav" && role != "place") return "target '" + item + "': role must be uav, place or ground";
    const std::string idx = item.substr(colon + 1);
    const auto dash = idx.find('-');
    uint32_t lo = 0, hi = 0;
    if (dash == std::string::npos) {
      if (!parse_uint(idx, lo)) return "target '" + item + "': bad index";
      hi = lo;
    } else if (!parse_uint(idx.substr(0, dash), lo) || !parse_uint(idx.substr(dash + 1), hi) || hi < lo) {
      return "target '" + item + "': bad range (I-J with I <= J)";
    }
    if (hi - lo > 100000) return "target '" + item + "': range too large";
    for (uint32_t i = lo; i <= hi; ++i) out.push_back({role, i});
  }
  return {};
}

Result<FaultEvent> parse_event(const std::string& item) {
  FaultEvent e;
  e.text = item;
  std::vector<std::string> w;
  {
    std::stringstream ss(item);
    std::string x;
    while (ss >> x) w.push_back(x);
  }
  auto bad = [&](const std::string& why) { return Error{"'" + item + "': " + why + " (" + kGrammar + ")"}; };
  if (w.empty()) return bad("empty");
  const std::string& verb = w[0];
  if (verb == "kill")
    e.action = FaultAction::Kill;
  else if (verb == "stop")
    e.action = FaultAction::Stop;
  else if (verb == "restart")
    e.action = FaultAction::Restart;
  else if (verb == "standby")
    e.action = FaultAction::Standby;
  else if (verb == "partition")
    e.action = FaultAction::Partition;
  else if (verb == "loss")
    e.action = FaultAction::Loss;
  else
    return bad("unknown action '" + verb + "'");
  std::size_t i = 1;
  if (e.action == FaultAction::Loss) {
    if (i >= w.size() || !w[i].ends_with("%")) return bad("loss needs a share, e.g. 30%");
    const std::string p = w[i].substr(0, w[i].size() - 1);
    char* end = nullptr;
    const double v = std::strtod(p.c_str(), &end);
    if (p.empty() || end != p.c_str() + p.size() || !(v > 0) || v > 100) return bad("loss share must be in (0, 100]%");
    e.loss = v / 100.0;
    ++i;
  }
  // Targets: every word up to the '@' word (or a 'for' that came too early).
  std::string targets;
  while (i < w.size() && !w[i].starts_with("@") && w[i] != "for") targets += w[i++] + ",";
  if (auto err = parse_targets(targets, e.targets)) return bad(*err);
  if (e.targets.empty() && e.action != FaultAction::Loss) return bad("no targets");
  if (i >= w.size() || !w[i].starts_with("@")) return bad("no time (@TIME)");
  std::string at = w[i++].substr(1);
  if (at.empty() && i < w.size()) at = w[i++];  // "@ 5s"
  if (auto err = parse_time(at, e.at_s, e.at_tick)) return bad(*err);
  if (i < w.size() && w[i] == "for") {
    if (i + 1 >= w.size()) return bad("'for' needs a duration");
    if (auto err = parse_duration(w[i + 1], e.duration_s)) return bad(*err);
    i += 2;
  } else if (e.action == FaultAction::Stop || e.action == FaultAction::Partition || e.action == FaultAction::Loss) {
    return bad(std::string(to_string(e.action)) + " needs 'for DURATION'");
  }
  if (i < w.size()) return bad("unexpected '" + w[i] + "'");
  if ((e.action == FaultAction::Stop || e.action == FaultAction::Partition || e.action == FaultAction::Loss) &&
      !(e.duration_s > 0)) {
    return bad("the duration must be positive");
  }
  if (e.action == FaultAction::Standby) {
    for (const auto& t : e.targets) {
      if (t.role != "place") return bad("standby starts place agents only (place:R)");
    }
  }
  return e;
}

double sort_key(const FaultEvent& e) { return e.at_tick ? static_cast<double>(*e.at_tick) : *e.at_s; }

// The older --kill form: "uav:3@5s,place:1@2500ms".
bool looks_like_kill_spec(const std::string& text) {
  const std::string t = trim(text);
  return !t.empty() && (t.starts_with("uav:") || t.starts_with("place:")) && t.find(' ') == std::string::npos &&
         t.find(';') == std::string::npos;
}

}  // namespace

Result<FaultSchedule> parse_fault_schedule(const std::string& text, const std::string& where) {
  FaultSchedule s;
  std::vector<std::string> items;
  if (looks_like_kill_spec(text)) {
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
      item = trim(item);
      if (item.empty()) continue;
      const auto at = item.find('@');
      if (at == std::string::npos) return Error{where + ": '" + item + "': expected ROLE:INDEX@TIME, e.g. uav:3@5s"};
      items.push_back("kill " + item.substr(0, at) + " @" + item.substr(at + 1));
    }
  } else {
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ';')) {
      item = trim(item);
      if (!item.empty()) items.push_back(item);
    }
  }
  if (items.empty()) return Error{where + ": no fault events in '" + text + "'"};
  for (const auto& item : items) {
    auto e = parse_event(item);
    if (!e) return Error{where + ": " + e.error().message};
    s.events.push_back(std::move(e).value());
  }
  const bool ticks = s.events.front().at_tick.has_value();
  for (const auto& e : s.events) {
    if (e.at_tick.has_value() != ticks) {
      return Error{where + ": '" + e.text + "': mixes tick times (t) with wall times (s, ms); use one clock"};
    }
  }
  std::stable_sort(s.events.begin(), s.events.end(),
                   [](const FaultEvent& a, const FaultEvent& b) { return sort_key(a) < sort_key(b); });
  return s;
}

bool FaultSchedule::in_ticks() const {
  return !events.empty() &&
         std::all_of(events.begin(), events.end(), [](const auto& e) { return e.at_tick.has_value(); });
}

bool FaultSchedule::has_network() const {
  return std::any_of(events.begin(), events.end(),
                     [](const auto& e) { return e.action == FaultAction::Partition || e.action == FaultAction::Loss; });
}

namespace {
std::vector<std::pair<uint32_t, uint32_t>> kills_of(const FaultSchedule& s, const char* role) {
  std::vector<std::pair<uint32_t, uint32_t>> out;
  for (const auto& e : s.events) {
    if (e.action != FaultAction::Kill || !e.at_tick) continue;
    for (const auto& t : e.targets) {
      if (t.role != role) continue;
      const bool seen = std::any_of(out.begin(), out.end(), [&](const auto& p) { return p.first == t.index; });
      if (!seen) out.emplace_back(t.index, *e.at_tick);
    }
  }
  return out;
}
}  // namespace

std::vector<std::pair<uint32_t, uint32_t>> FaultSchedule::uav_kills() const { return kills_of(*this, "uav"); }
std::vector<std::pair<uint32_t, uint32_t>> FaultSchedule::place_kills() const { return kills_of(*this, "place"); }

std::optional<std::string> check_fault_schedule(const FaultSchedule& s, uint32_t uavs, uint32_t regions,
                                                bool lockstep) {
  for (const auto& e : s.events) {
    if (lockstep && !e.at_tick) {
      return "'" + e.text + "': a lockstep run (and the simulator) times faults in ticks, e.g. @40t";
    }
    if (!lockstep && e.at_tick) return "'" + e.text + "': a realtime run times faults in s or ms, e.g. @5s";
    for (const auto& t : e.targets) {
      if (t.role == "uav" && t.index >= uavs) {
        return "'" + e.text + "': " + t.process_name() + " does not exist (this swarm has " + std::to_string(uavs) +
               " UAVs: uav:0-" + std::to_string(uavs == 0 ? 0 : uavs - 1) + ")";
      }
      if (t.role == "place" && t.index >= regions) {
        return "'" + e.text + "': " + t.process_name() + " does not exist (this map has " + std::to_string(regions) +
               " regions: place:0-" + std::to_string(regions == 0 ? 0 : regions - 1) + ")";
      }
    }
  }
  return {};
}

void merge_fault_schedules(FaultSchedule& a, const FaultSchedule& b) {
  a.events.insert(a.events.end(), b.events.begin(), b.events.end());
  std::stable_sort(a.events.begin(), a.events.end(),
                   [](const FaultEvent& x, const FaultEvent& y) { return sort_key(x) < sort_key(y); });
}

}  // namespace pheromesh::core
