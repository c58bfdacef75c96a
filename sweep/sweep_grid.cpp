#include "sweep_grid.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <set>

namespace pheromesh::cli::sweep {

namespace {

// A whole decimal number without sign or spaces, as a seed.
bool parse_u64(std::string_view s, uint64_t& out) {
  if (s.empty()) return false;
  const auto* end = s.data() + s.size();
  const auto [p, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc{} && p == end;
}

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t");
  return std::string(s.substr(b, e - b + 1));
}

}  // namespace

std::string Parameter::source() const {
  if (flag != "--set") return flag == "--standby" ? flag : flag + " " + (values.empty() ? "" : values.front());
  std::string s = "--set " + path + "=";
  for (std::size_t i = 0; i < values.size(); ++i) s += (i == 0 ? "" : ",") + values[i];
  return s;
}

core::Result<std::vector<uint64_t>> parse_seeds(const std::string& text) {
  std::vector<uint64_t> out;
  std::set<uint64_t> seen;
  const std::string form = " (give seeds and ranges separated by commas, e.g. --seeds 1-20 or --seeds 1,5,9)";
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = trim(std::string_view(text).substr(start, comma - start));
    start = comma + 1;
    if (item.empty()) return core::Error{"--seeds " + text + ": an empty item" + form};
    const std::size_t dash = item.find('-');
    uint64_t lo = 0, hi = 0;
    if (dash == std::string::npos) {
      if (!parse_u64(item, lo)) return core::Error{"--seeds " + text + ": '" + item + "' is not a whole number" + form};
      hi = lo;
    } else {
      const std::string a = trim(std::string_view(item).substr(0, dash));
      const std::string b = trim(std::string_view(item).substr(dash + 1));
      if (!parse_u64(a, lo) || !parse_u64(b, hi)) {
        return core::Error{"--seeds " + text + ": '" + item + "' is not a range FIRST-LAST of whole numbers" + form};
      }
      if (hi < lo) {
        return core::Error{"--seeds " + text + ": the range '" + item + "' ends before it starts"};
      }
    }
    if (hi - lo >= kMaxRuns || out.size() + (hi - lo + 1) > kMaxRuns) {
      return core::Error{"--seeds " + text + ": more than " + std::to_string(kMaxRuns) + " seeds"};
    }
    for (uint64_t s = lo;; ++s) {
      if (!seen.insert(s).second) {
        return core::Error{"--seeds " + text + ": seed " + std::to_string(s) + " is given twice"};
      }
      out.push_back(s);
      if (s == hi) break;
    }
  }
  return out;
}

core::Result<Parameter> parse_set_list(const std::string& arg) {
  const std::size_t eq = arg.find('=');
  if (eq == std::string::npos || eq == 0) {
    return core::Error{"--set " + arg +
                       ": expected PATH=V1,V2,..., a field path of the scenario and its values, e.g. --set "
                       "shao.aco.alpha=1,2,3"};
  }
  Parameter p;
  p.path = arg.substr(0, eq);
  const std::string list = arg.substr(eq + 1);
  std::string value;
  bool quoted = false;
  auto finish = [&]() -> core::Result<bool> {
    if (value.empty()) {
      return core::Error{"--set " + arg + ": value " + std::to_string(p.values.size() + 1) +
                         " is empty (values are separated by commas; a comma inside double quotes is part of "
                         "the value)"};
    }
    if (std::find(p.values.begin(), p.values.end(), value) != p.values.end()) {
      return core::Error{"--set " + arg + ": the value " + value + " is given twice"};
    }
    p.values.push_back(std::move(value));
    value.clear();
    return true;
  };
  for (char c : list) {
    if (c == '"') quoted = !quoted;
    if (c == ',' && !quoted) {
      if (auto r = finish(); !r) return r.error();
      continue;
    }
    value += c;
  }
  if (quoted) return core::Error{"--set " + arg + ": a double quote is not closed"};
  if (auto r = finish(); !r) return r.error();
  return p;
}

core::Result<std::vector<Parameter>> parameters_of(const OverrideFlags& flags) {
  if (flags.seed) {
    return core::Error{"--seed " + *flags.seed + ": a sweep takes its seeds from --seeds (e.g. --seeds 1-20)"};
  }
  if (flags.duration_s) return core::Error{"--duration: a sweep runs the simulator; give run.ticks (--ticks N)"};
  std::vector<Parameter> out;
  if (flags.uavs) out.push_back({"swarm.uavs", {*flags.uavs}, "--uavs"});
  if (flags.ticks) out.push_back({"run.ticks", {*flags.ticks}, "--ticks"});
  if (flags.rate) out.push_back({"run.tick_rate_hz", {*flags.rate}, "--rate"});
  if (flags.standby) out.push_back({"run.standby", {"true"}, "--standby"});
  for (const auto& arg : flags.set) {
    auto p = parse_set_list(arg);
    if (!p) return p.error();
    if (p->path == "run.seed") {
      return core::Error{"--set " + arg + ": a sweep takes its seeds from --seeds (e.g. --seeds 1-20), not run.seed"};
    }
    for (const auto& q : out) {
      if (q.path == p->path) {
        return core::Error{q.source() + " and --set " + arg + " both set " + p->path + "; give one of them"};
      }
    }
    out.push_back(std::move(p).value());
  }
  return out;
}

std::vector<Cell> grid(const std::vector<Parameter>& params) {
  std::size_t count = 1;
  for (const auto& p : params) count *= p.values.size();
  std::vector<Cell> cells;
  cells.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    Cell c;
    c.index = i;
    c.choice.resize(params.size());
    // Mixed radix, the last parameter fastest.
    std::size_t rest = i;
    for (std::size_t k = params.size(); k-- > 0;) {
      c.choice[k] = rest % params[k].values.size();
      rest /= params[k].values.size();
    }
    cells.push_back(std::move(c));
  }
  return cells;
}

OverrideFlags cell_flags(const std::vector<Parameter>& params, const Cell& cell, uint64_t seed) {
  OverrideFlags f;
  for (std::size_t k = 0; k < params.size(); ++k) {
    const auto& p = params[k];
    const std::string& v = p.values.at(cell.choice.at(k));
    if (p.flag == "--uavs") {
      f.uavs = v;
    } else if (p.flag == "--ticks") {
      f.ticks = v;
    } else if (p.flag == "--rate") {
      f.rate = v;
    } else if (p.flag == "--standby") {
      f.standby = true;
    } else {
      f.set.push_back(p.path + "=" + v);
    }
  }
  f.seed = std::to_string(seed);
  return f;
}

std::string describe_cell(const std::vector<Parameter>& params, const Cell& cell) {
  std::string s;
  for (std::size_t k = 0; k < params.size(); ++k) {
    if (!params[k].swept()) continue;
    s += (s.empty() ? "" : ", ") + params[k].path + "=" + params[k].values.at(cell.choice.at(k));
  }
  return s.empty() ? "(no swept parameter)" : s;
}

core::Result<std::vector<Run>> runs_of(const std::vector<Cell>& cells, const std::vector<uint64_t>& seeds) {
  if (!seeds.empty() && cells.size() > kMaxRuns / seeds.size()) {
    return core::Error{std::to_string(cells.size()) + " combinations x " + std::to_string(seeds.size()) +
                       " seeds is more than " + std::to_string(kMaxRuns) + " runs"};
  }
  const int width = cells.size() > 1000 ? static_cast<int>(std::to_string(cells.size() - 1).size()) : 3;
  std::vector<Run> runs;
  runs.reserve(cells.size() * seeds.size());
  for (const auto& c : cells) {
    for (uint64_t s : seeds) {
      char id[64];
      std::snprintf(id, sizeof id, "c%0*zu-s%llu", width, c.index, static_cast<unsigned long long>(s));
      runs.push_back({c.index, s, id});
    }
  }
  return runs;
}

std::vector<std::size_t> sample_runs(std::size_t run_count, std::size_t k) {
  std::vector<std::size_t> out;
  if (run_count == 0 || k == 0) return out;
  k = std::min(k, run_count);
  for (std::size_t i = 0; i < k; ++i) out.push_back(i * run_count / k);
  return out;
}

nlohmann::json definition_json(const std::string& scenario_name, const std::vector<Parameter>& params,
                               const std::vector<uint64_t>& seeds) {
  nlohmann::json j;
  j["scenario"] = scenario_name;
  j["parameters"] = nlohmann::json::array();
  for (const auto& p : params) j["parameters"].push_back({{"path", p.path}, {"values", p.values}, {"flag", p.flag}});
  j["seeds"] = describe_seeds(seeds);  // short (1-1000), and one text per list
  return j;
}

std::string definition_change(const nlohmann::json& stored, const nlohmann::json& wanted) {
  std::string d;
  auto add = [&](const std::string& what) { d += (d.empty() ? "" : "; ") + what; };
  auto get = [](const nlohmann::json& j, const char* key) {
    return j.is_object() && j.contains(key) ? j[key] : nlohmann::json();
  };
  if (get(stored, "scenario") != get(wanted, "scenario")) {
    add("scenario: " + get(stored, "scenario").dump() + " before, " + get(wanted, "scenario").dump() + " now");
  }
  if (get(stored, "parameters") != get(wanted, "parameters")) {
    auto show = [](const nlohmann::json& ps) {
      std::string s;
      if (!ps.is_array()) return std::string("none");
      try {
        for (const auto& p : ps) {
          Parameter q;
          q.path = p.value("path", "");
          q.flag = p.value("flag", "--set");
          if (p.contains("values") && p["values"].is_array()) q.values = p["values"].get<std::vector<std::string>>();
          s += (s.empty() ? "" : " ") + q.source();
        }
      } catch (const nlohmann::json::exception&) {
        return ps.dump();  // a hand-edited sweep.json: show it as it is
      }
      return s.empty() ? std::string("none") : s;
    };
    add("parameters: " + show(get(stored, "parameters")) + " before, " + show(get(wanted, "parameters")) + " now");
  }
  if (get(stored, "seeds") != get(wanted, "seeds")) {
    add("seeds: " + get(stored, "seeds").dump() + " before, " + get(wanted, "seeds").dump() + " now");
  }
  return d;
}

std::string describe_seeds(const std::vector<uint64_t>& seeds) {
  std::string s;
  for (std::size_t i = 0; i < seeds.size();) {
    std::size_t j = i;
    while (j + 1 < seeds.size() && seeds[j + 1] == seeds[j] + 1) ++j;
    s += (s.empty() ? "" : ", ") + std::to_string(seeds[i]);
    if (j > i) s += (j == i + 1 ? ", " : "-") + std::to_string(seeds[j]);
    i = j + 1;
  }
  return s;
}

}  // namespace pheromesh::cli::sweep
