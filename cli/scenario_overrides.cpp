#include "scenario_overrides.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace pheromesh::cli {

namespace {

struct FieldFlagInfo {
  FieldFlag flag;
  const char* name;   // "--uavs"
  const char* path;   // "swarm.uavs"
  const char* value;  // "N"
  const char* help;
};

constexpr FieldFlagInfo kFieldFlags[] = {
    {FieldFlag::Uavs, "--uavs", "swarm.uavs", "N", "Number of UAVs, 1..5000"},
    {FieldFlag::Ticks, "--ticks", "run.ticks", "N", "Ticks to run, >= 1"},
    {FieldFlag::Seed, "--seed", "run.seed", "N", "Run seed"},
    {FieldFlag::Rate, "--rate", "run.tick_rate_hz", "HZ", "Tick rate of every process [Hz], (0, 1000]"},
};

// The member of `f` a FieldFlag fills (const or not, as `f`).
template <class Flags>
auto& value_of(Flags& f, FieldFlag which) {
  switch (which) {
    case FieldFlag::Uavs:
      return f.uavs;
    case FieldFlag::Ticks:
      return f.ticks;
    case FieldFlag::Seed:
      return f.seed;
    case FieldFlag::Rate:
      break;
  }
  return f.rate;
}

}  // namespace

const char* const kSetFooter = R"(OVERRIDES (docs/scenario-format.md, "Overrides")
  --set PATH=VALUE changes one field of the scenario after it is read: PATH is the
  field's path in the textproto (scenario.proto), VALUE is parsed for its type.
  Repeatable; the changed scenario is validated exactly like a file, and an error
  about an overridden field names the --set. Where a command has them, --uavs,
  --ticks, --seed, --rate and --standby stand for --set swarm.uavs, run.ticks,
  run.seed, run.tick_rate_hz and run.standby=true.
    --set swarm.uavs=20 --set shao.aco.alpha=2
    --set policy.shao_search.search=frontier        a member of the policy oneof
    --set map.targets[2].x=14                        an entry of a repeated field
)";

CLI::Option* add_override_options(CLI::App& cmd, OverrideFlags& flags, const std::vector<FieldFlag>& fields) {
  cmd.add_option("--set", flags.set,
                 "Change a field of the scenario: PATH=VALUE, e.g. --set swarm.uavs=20 --set shao.aco.alpha=2; "
                 "repeatable; validated like the file (see OVERRIDES below)")
      ->type_name("PATH=VALUE")
      ->allow_extra_args(false);
  CLI::Option* ticks = nullptr;
  for (const auto& info : kFieldFlags) {
    if (std::find(fields.begin(), fields.end(), info.flag) == fields.end()) continue;
    auto* opt = cmd.add_option(info.name, value_of(flags, info.flag),
                               std::string(info.help) + " (default: the scenario's " + info.path +
                                   "; stands for --set " + info.path + "=" + info.value + ")")
                    ->type_name(info.value);
    if (info.flag == FieldFlag::Ticks) ticks = opt;
  }
  return ticks;
}

core::Result<core::ScenarioOverrides> overrides_of(const OverrideFlags& flags) {
  core::ScenarioOverrides out;
  for (const auto& info : kFieldFlags) {
    if (const auto& v = value_of(flags, info.flag)) {
      out.push_back({info.path, *v, std::string(info.name) + " " + *v});
    }
  }
  if (flags.standby) out.push_back({"run.standby", "true", "--standby"});
  const std::size_t by_flags = out.size();
  for (const auto& arg : flags.set) {
    auto o = core::parse_override(arg);
    if (!o) return o.error();
    for (std::size_t i = 0; i < by_flags; ++i) {
      if (out[i].path == o->path) {
        return core::Error{out[i].source + " and " + o->source + " both set " + o->path + "; give one of them"};
      }
    }
    out.push_back(std::move(o).value());
  }
  return out;
}

core::Result<core::ScenarioConfig> load_overridden(const std::string& path, const OverrideFlags& flags) {
  auto overrides = overrides_of(flags);
  if (!overrides) return overrides.error();
  auto s = core::load_scenario(path, overrides.value());
  if (!s || !flags.duration_s) return s;
  // --duration: run.ticks from the rate the overrides left.
  const double d = *flags.duration_s;
  char shown[32];
  std::snprintf(shown, sizeof shown, "%g", d);
  const std::string source = std::string("--duration ") + shown;
  if (!std::isfinite(d) || d <= 0) return core::Error{source + ": must be a number of seconds > 0"};
  const double ticks = std::ceil(d * s->tick_rate_hz);
  if (ticks > std::numeric_limits<uint32_t>::max()) {
    return core::Error{source + ": " + std::to_string(ticks) + " ticks at " + std::to_string(s->tick_rate_hz) +
                       " Hz, more than run.ticks can hold"};
  }
  for (const auto& o : overrides.value()) {
    if (o.path == "run.ticks")
      return core::Error{o.source + " and " + source + " both set run.ticks; give one of them"};
  }
  overrides->push_back({"run.ticks", std::to_string(static_cast<uint64_t>(ticks)), source});
  return core::load_scenario(path, overrides.value());
}

std::string describe_override(const core::ScenarioOverride& o) {
  if (o.source.find(o.path) != std::string::npos) return o.source;
  return o.source + " (" + o.path + "=" + o.value + ")";
}

std::string overrides_summary(const core::ScenarioConfig& s) {
  std::string out;
  for (const auto& o : s.overrides) {
    out += std::string(out.empty() ? "  overrides   " : "              ") + describe_override(o) + "\n";
  }
  return out;
}

std::string policy_summary(const core::ScenarioConfig& s) {
  if (s.python) {
    return s.policy + " from the Python class " + s.python->module + "." + s.python->class_name + " (" + s.python->file +
           ")";
  }
  if (!s.plugin) return s.policy;
  return s.policy + " from the plugin " + s.plugin->library + " (SHA-256 " + s.plugin->sha256 + ", " +
         (s.plugin->pinned_by.empty() ? std::string("not pinned") : "pinned by " + s.plugin->pinned_by) + ")";
}

}  // namespace pheromesh::cli
