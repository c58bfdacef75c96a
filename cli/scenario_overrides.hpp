// The flags that change a scenario's fields on the command line: `--set
// PATH=VALUE` of validate, sim, run and experiment (and a later sweep), and
// the flags that stand for one (`--uavs N` is `--set swarm.uavs=N`). Every
// one of them becomes a core::ScenarioOverride, applied to the parsed file
// and validated with it (core::load_scenario), so a value the file may not
// hold is refused on the command line too, naming the flag.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/result.hpp"
#include "pheromesh/core/scenario.hpp"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace pheromesh::cli {

// The flags that stand for an override of one field.
enum class FieldFlag : uint8_t {
  Uavs,   // --uavs N     swarm.uavs
  Ticks,  // --ticks N    run.ticks
  Seed,   // --seed N     run.seed
  Rate,   // --rate HZ    run.tick_rate_hz
};

struct OverrideFlags {
  std::vector<std::string> set;  // --set PATH=VALUE, in the order given
  // The FieldFlag flags, as typed (parsed for the field's type like --set).
  std::optional<std::string> uavs, ticks, seed, rate;
  // `run --duration D` in seconds (D parsed by cli::parse_duration_s: 20, 90s,
  // 10m): run.ticks = ceil(seconds x the run's rate), after the other
  // overrides (which may change the rate).
  std::optional<double> duration_s;
  // `--standby` of run and sim: --set run.standby=true (each command adds
  // the flag with its own help).
  bool standby = false;
};

// Adds --set and the flags of `fields` to `cmd`, bound to `flags`; returns
// the --ticks option if asked for (run: --duration excludes it), else null.
CLI::Option* add_override_options(CLI::App& cmd, OverrideFlags& flags, const std::vector<FieldFlag>& fields);

// The lines on --set that each command's help ends with.
extern const char* const kSetFooter;

// The overrides the flags ask for, the field flags first, then every --set in
// order; an error for a malformed --set, or a field set by a flag and by
// --set both (which one would win is not obvious on a command line).
// --duration is not among them: it needs the scenario (load_overridden).
core::Result<core::ScenarioOverrides> overrides_of(const OverrideFlags& flags);

// The scenario file with the flags' overrides applied, validated as a file
// is; --duration becomes run.ticks at the rate of the changed scenario. The
// one way the CLI changes a scenario from flags.
core::Result<core::ScenarioConfig> load_overridden(const std::string& path, const OverrideFlags& flags);

// "--uavs 6 (swarm.uavs=6)", "--set swarm.uavs=20": an override as the user
// gave it, with the field it set when the flag does not say.
std::string describe_override(const core::ScenarioOverride& o);

// "  overrides   --set a=1" lines (one per override) for validate, or "" for none.
std::string overrides_summary(const core::ScenarioConfig& s);
// "liu", or "NAME from the plugin LIB (SHA-256 X, pinned by ...)": which code
// a scenario runs, for validate and run.
std::string policy_summary(const core::ScenarioConfig& s);

}  // namespace pheromesh::cli
