// pheromesh: the front door. `validate` checks a scenario, `sim`, `experiment`
// and `sweep` run the core in this process; `run` launches a whole swarm on
// this host, with the other subcommands that need DDS or the web console
// (process_commands.hpp; absent from a core-only build).
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>

#include "experiments/experiment_command.hpp"
#include "pheromesh/auth/control.hpp"
#include "pheromesh/cliutil/command_line.hpp"
#include "pheromesh/cliutil/scenario_paths.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/policy_table.hpp"
#include "pheromesh/core/scenario_limits.hpp"
#include "pheromesh/core/scenario_warnings.hpp"
#include "process_commands.hpp"
#include "scenario_overrides.hpp"
#include "pheromesh/cliutil/scenario_paths.hpp"
#include "sim_command.hpp"
#include "sweep/sweep_command.hpp"
#ifdef PHEROMESH_WITH_PYTHON
#include "pheromesh/pypolicy/enable.hpp"  // policies written in Python (docs/python.md)
#endif

namespace {

// Prints a scenario's fault lines under `pheromesh validate`.
void print_faults(const pheromesh::core::FaultSchedule& f) {
  if (f.empty()) {
    std::printf("  faults      none\n");
    return;
  }
  std::printf("  faults      %zu events, timed in %s\n", f.events.size(),
              f.in_ticks() ? "ticks (lockstep runs)" : "seconds (realtime runs)");
  for (const auto& e : f.events) std::printf("              %s\n", e.text.c_str());
}

// Ticks `validate` flies a plugin's or Python policy in the simulator to
// check its max_step (core::max_step_trial).
constexpr uint32_t kMaxStepTrialTicks = 20;

int validate(const std::string& path, const pheromesh::cli::OverrideFlags& overrides) {
  auto env_limits = pheromesh::core::ScenarioLimits::from_environment();
  if (!env_limits) {
    std::fprintf(stderr, "%s\n", env_limits.error().message.c_str());
    return 2;
  }
  const pheromesh::core::ScenarioLimits limits = env_limits.value();
  auto s = pheromesh::cli::load_overridden(path, overrides);
  if (!s) {
    std::fprintf(stderr, "%s\n", s.error().message.c_str());
    return 2;
  }
  const auto geo = s->geometry();
  std::printf("%s: OK\n  name        %s\n  policy      %s\n"
              "  map         %d x %d cells, tiles %d x %d of %d cells, %u regions (%d x %d)\n"
              "  obstacles   %zu rectangles\n  targets     %zu\n  uavs        %u\n  run         %u ticks at %.1f Hz, seed %llu\n",
              path.c_str(), s->name.c_str(), pheromesh::cli::policy_summary(s.value()).c_str(), s->width, s->height,
              geo.tiles_x(), geo.tiles_y(), s->tile_size, geo.region_count(), s->regions_x, s->regions_y,
              s->obstacles.size(), s->targets.size(), s->uavs, s->ticks, s->tick_rate_hz,
              static_cast<unsigned long long>(s->seed));
  // shao.aco.revisit_period is the Shao policies' (Shao 2020 Sec. 4.2); the
  // others never read it.
  if (const auto* entry = pheromesh::core::find_policy(s->policy); entry != nullptr && entry->parse_scenario_fields) {
    std::printf("  revisit     every %u ticks\n", s->aco.revisit_period);
  }
  for (const auto& w : pheromesh::core::scenario_warnings(s.value())) std::printf("  warning     %s\n", w.c_str());
  // A policy from outside (a plugin, Python) flown a few ticks in the
  // simulator: a max_step below what its moves need shows as refused
  // states (docs/writing-a-policy.md, "How far a UAV may fly"). The
  // built-in policies are held to theirs by HonestRuns.* (unit tests).
  if (s->plugin || s->python) {
    for (const auto& w : pheromesh::core::max_step_trial(s.value(), kMaxStepTrialTicks)) {
      std::printf("  warning     max_step: %s\n", w.c_str());
    }
  }
  std::printf("%s", pheromesh::cli::overrides_summary(s.value()).c_str());
  print_faults(s->faults);
  // The figures the limits are checked against (scenario_limits.hpp).
  const auto cost = pheromesh::core::estimate_cost(s.value());
  std::printf("  processes   %lld (limit %lld, $%s)\n  memory      ~%.0f MiB for the largest process, the %s "
              "(limit %lld MiB, $%s); ~%.0f MiB for the swarm (limit %lld MiB, $%s)\n",
              static_cast<long long>(cost.processes), static_cast<long long>(limits.max_processes),
              pheromesh::core::kMaxProcessesEnv, cost.largest_mib(), cost.largest_role(),
              static_cast<long long>(limits.max_process_mib), pheromesh::core::kMaxProcessMibEnv, cost.swarm_mib,
              static_cast<long long>(limits.max_swarm_mib), pheromesh::core::kMaxSwarmMibEnv);
  return 0;
}

// The front door's own commands: their options, filled in by the parse, and
// their subcommands, to ask which one was given.
struct FrontDoor {
  std::string log_level = "info";
  std::string validate_path;
  pheromesh::cli::OverrideFlags validate_overrides;
  pheromesh::cli::SimOptions so;
  pheromesh::cli::SweepOptions swo;
  pheromesh::cli::ExperimentOptions eo;
  CLI::App* v = nullptr;
  CLI::App* sim = nullptr;
  CLI::App* sw = nullptr;
  CLI::App* ex = nullptr;
  CLI::App* key = nullptr;
};

void add_validate_command(CLI::App& app, FrontDoor& fd) {
  using namespace pheromesh;
  std::string& validate_path = fd.validate_path;
  cli::OverrideFlags& validate_overrides = fd.validate_overrides;
  CLI::App* v = fd.v = app.add_subcommand(
      "validate",
      "Check a scenario file and print its policy, size, run and cost, with a warning for each block its policy "
      "ignores; errors name the file, line and field. Also refused: strings that are not UTF-8, and "
      "scenarios beyond the limits on map cells, regions, processes and estimated memory (raise them with "
      "$PHEROMESH_MAX_MAP_CELLS, _REGIONS, _PROCESSES, _PROCESS_MIB, _SWARM_MIB; docs/scenario-format.md)");
  v->add_option("SCENARIO", validate_path, cli::kScenarioArgHelp)
      ->required()
      ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
  cli::add_override_options(*v, validate_overrides,
                            {cli::FieldFlag::Uavs, cli::FieldFlag::Ticks, cli::FieldFlag::Seed, cli::FieldFlag::Rate});
  v->footer(std::string(cli::kSetFooter) + R"(
Examples:
  pheromesh validate small-test
  pheromesh validate small-test --set swarm.uavs=8 --set shao.aco.alpha=2    prints the overrides it applied)");
}

void add_sim_command(CLI::App& app, FrontDoor& fd) {
  using namespace pheromesh;
  cli::SimOptions& so = fd.so;
  CLI::App* sim = fd.sim =
      app.add_subcommand("sim",
                         "Run the whole swarm in this process, deterministically (no DDS): the same "
                         "core code and lockstep schedule as `run --clock lockstep`, the same "
                         "OUT/metrics.json, series.csv and final_field.txt/.csv (docs/outputs.md)");
  sim->add_option("SCENARIO", so.scenario, cli::kScenarioArgHelp)
      ->required()
      ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
  cli::add_override_options(*sim, so.overrides, {cli::FieldFlag::Seed, cli::FieldFlag::Ticks, cli::FieldFlag::Uavs});
  sim->add_option("--out", so.out_dir, "Output folder, relative to the current directory")->capture_default_str();
  sim->add_flag("--quiet", so.quiet, "No progress lines");
  sim->add_option("--faults", so.faults,
                  "Fault schedule timed in ticks, e.g. \"kill uav:3 @40t; kill place:1 @60t\" (docs/faults.md); "
                  "stop, partition and loss do not change simulated numbers");
  sim->add_flag("--tracks", so.tracks, "Also write OUT/tracks.csv: every UAV's position and role at every tick");
  sim->add_option("--record", so.record,
                  "Record the run as a console recording for `pheromesh replay FILE` (simulated time; "
                  "docs/outputs.md)");
  sim->add_flag("--strict", so.strict,
                "Fail the run (exit 9) if a UAV's state was refused as implausible: its policy moved further in a "
                "tick than its max_step allows (docs/writing-a-policy.md)");
  sim->add_flag("--standby", so.overrides.standby,
                "Every place agent has a standby that takes over when it is killed; stands for --set "
                "run.standby=true");
  sim->footer(std::string(cli::kSetFooter) + R"(
Examples:
  pheromesh sim small-test --ticks 100 --out out/sim
  pheromesh sim small-test --set shao.aco.alpha=2 --set swarm.uavs=8 --seed 3)");
}

void add_sweep_command(CLI::App& app, FrontDoor& fd) {
  using namespace pheromesh;
  cli::SweepOptions& swo = fd.swo;
  CLI::App* sw = fd.sw = app.add_subcommand(
      "sweep",
      "Run a scenario on the in-process simulator for every combination of parameter values (--set "
      "PATH=V1,V2,...) and every seed (--seeds 1-20), in parallel (--jobs) and resumably; write runs.csv, "
      "summary.csv (mean, sd, 95 % interval per combination), SVG plots and sweep.md; print runs/s");
  sw->add_option("SCENARIO", swo.scenario, cli::kScenarioArgHelp)
      ->required()
      ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
  cli::add_override_options(*sw, swo.overrides, {cli::FieldFlag::Ticks, cli::FieldFlag::Uavs});
  sw->get_option("--set")
      ->description("The values of a field: PATH=V1,V2,... (one value: a fixed override); repeatable, every "
                    "combination is run; each value validated like the file (see GRID below)")
      ->type_name("PATH=V1,V2,...");
  sw->add_option("--seeds", swo.seeds, "Seeds of every combination: 1-20, 1,5,9 or 1-3,10")->capture_default_str();
  sw->add_option("--jobs,-j", swo.jobs, "Simulations run at once (default: the host's hardware threads)")
      ->check(CLI::Range(1U, 1024U));
  sw->add_option("--out", swo.out_dir,
                 "Output folder, relative to the current directory (default out/sweeps/<scenario name>); a re-run "
                 "in the same folder skips the finished runs");
  sw->add_flag("--quiet", swo.quiet, "No progress bar");
  sw->add_flag("--distributed", swo.distributed,
               "Also fly a sample of the runs as processes (pheromesh run --clock lockstep) and check each against "
               "the simulator: metrics and final_field.txt; exit 4 if one differs");
  sw->add_option("--distributed-sample", swo.distributed_sample,
                 "With --distributed: how many runs to fly, spread over the sweep")
      ->check(CLI::Range(1U, 1000U))
      ->capture_default_str();
  sw->add_option("--dds", swo.dds, "With --distributed: the vendor(s) of the processes (cyclone, fastdds, mixed)")
      ->check(CLI::IsMember({"cyclone", "fastdds", "mixed"}))
      ->capture_default_str();
  sw->add_option("--domain", swo.domain, "With --distributed: the DDS domain of the processes")
      ->check(CLI::Range(0U, 232U))
      ->capture_default_str();
  sw->footer(std::string(cli::kSweepFooter) + "\n" + cli::kSetFooter);
}

void add_experiment_command(CLI::App& app, FrontDoor& fd) {
  using namespace pheromesh;
  cli::ExperimentOptions& eo = fd.eo;
  CLI::App* ex = fd.ex =
      app.add_subcommand("experiment",
                         "Run one of the papers' experiments as Monte Carlo with the simulator and "
                         "write a report (Markdown + CSV + SVG) with our numbers beside the paper's");
  ex->add_option("NAME", eo.name, "Experiment (see --list)");
  ex->add_flag("--list", eo.list, "List the experiments and our verdict on each paper claim");
  ex->add_flag("--all", eo.all,
               "Run every experiment (each with --runs or its paper's count) and write OUT/summary.md: every paper "
               "figure beside ours with its verdict, the variants' gains and the wall times (OUT: --out, default "
               "out/experiments)");
  ex->add_option("--runs", eo.runs, "Monte Carlo runs, >= 1 (default: the paper's count)")
      ->check(CLI::Range(1U, 1000000U));
  ex->add_option("--out", eo.out_dir, "Output folder (default out/experiments/NAME)");
  ex->add_flag("--distributed", eo.distributed,
               "Also fly each run of the Monte Carlo as real processes (pheromesh run --clock lockstep) and check "
               "that its numbers equal the simulator's for the same seed; use a small --runs");
  ex->add_option("--dds", eo.dds, "With --distributed: the vendor(s) of the processes (cyclone, fastdds, mixed)")
      ->check(CLI::IsMember({"cyclone", "fastdds", "mixed"}))
      ->capture_default_str();
  ex->add_option("--domain", eo.domain, "With --distributed: the DDS domain of the processes")
      ->check(CLI::Range(0U, 232U))
      ->capture_default_str();
  cli::add_override_options(*ex, eo.overrides, {});
  ex->footer(R"(Examples:
  pheromesh experiment --list                       every experiment and our verdict on the paper's claims
  pheromesh experiment shao-50x50 --runs 30         Monte Carlo in the simulator, report in out/experiments/shao-50x50
  pheromesh experiment shao-50x50 --runs 3 --distributed --dds mixed
                                                    the same runs flown by real processes, checked against the simulator
  pheromesh experiment --all                        every experiment; out/experiments/summary.md sums them up
  pheromesh experiment shao-50x50 --runs 10 --set shao.aco.alpha=2
                                                    every scenario the experiment reads, changed (the report
                                                    names the overrides; run.seed is the experiment's)

)" + std::string(cli::kSetFooter));
}

// Runs the command the parse chose; an exception that escapes one is reported.
int dispatch(FrontDoor& fd, pheromesh::cli::ProcessCommands& processes, int argc, char** argv) {
  using namespace pheromesh;
  cli::SweepOptions& swo = fd.swo;
  const cli::ExperimentOptions& eo = fd.eo;
  CLI::App* v = fd.v;
  CLI::App* key = fd.key;
  CLI::App* ex = fd.ex;
  CLI::App* sw = fd.sw;
  CLI::App* sim = fd.sim;
  // Every command inside one try: an exception that escapes one (a policy
  // plugin's code may throw from any step, docs/writing-a-policy.md) is
  // reported and gives exit 4, never an abort without a message.
  try {
    if (v->parsed()) return validate(fd.validate_path, fd.validate_overrides);
    if (key->parsed()) {
      std::printf("%s\n", auth::random_control_key_hex().c_str());
      return 0;
    }
    if (((ex->parsed() && eo.distributed) || (sw->parsed() && swo.distributed)) && !cli::processes_built()) {
      std::fprintf(stderr, "--distributed flies runs as DDS processes (pheromesh run): %s\n", cli::kCoreOnlyHint);
      return 2;
    }
    if (sim->parsed()) return cli::run_sim(fd.so);
    if (ex->parsed()) return cli::run_experiment_command(eo);
    if (sw->parsed()) {
      swo.command = cli::command_line(argc, argv);
      return cli::run_sweep(swo);
    }
    if (auto rc = processes.run_parsed()) return *rc;
  } catch (const std::exception& e) {
    spdlog::critical("fatal: {}", e.what());
    return 4;
  }
  return 2;  // unreachable: require_subcommand(1)
}

}  // namespace

int main(int argc, char** argv) {
  using namespace pheromesh;
#ifdef PHEROMESH_WITH_PYTHON
  pypolicy::enable_python_policies();
#endif
  CLI::App app{
      "pheromesh: a UAV swarm coordinating through digital pheromones over DDS.\n\n"
      "Examples:\n"
      "  pheromesh validate scenarios/shao2020-50x50.textproto\n"
      "  pheromesh run scenarios/shao2020-50x50.textproto --ticks 600 --out out/demo\n"
      "  pheromesh run scenarios/small-test.textproto --uavs 6 --duration 20 --faults \"kill uav:1 @5s; stop uav:4 @8s "
      "for 3s\"\n"
      "  pheromesh sim scenarios/shao2020-100x100.textproto --seed 7 --out out/sim\n"
      "  pheromesh run scenarios/small-test.textproto --clock lockstep --ticks 100   # same numbers as sim\n"
      "  pheromesh bench scale scenarios/scale-100x100.textproto --max 400            # cost per swarm size\n"
      "  pheromesh bench lockstep --swarms small-test:10 --dds cyclone                 # where a lockstep tick's time "
      "goes\n",
      "pheromesh"};
  app.require_subcommand(1);
  app.footer("`pheromesh help SUBCOMMAND` (or `pheromesh SUBCOMMAND --help`) explains one.");
  cli::add_version_flag(app);
  FrontDoor fd;
  app.add_option("--log-level", fd.log_level,
                 "Log level of this program: trace, debug, info, warn, error, critical or off (run's processes: "
                 "--process-log-level)")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
      ->capture_default_str();

  add_validate_command(app, fd);
  add_sim_command(app, fd);
  add_sweep_command(app, fd);
  add_experiment_command(app, fd);
  fd.key = app.add_subcommand("key",
                              "Print a new random control key (64 hex digits) for $PHEROMESH_CONTROL_KEY: "
                              "every host of a swarm over several hosts exports the same one");
  // run, attach, bench, security, replay (or, built core-only, what they need).
  const auto processes = cli::add_process_commands(app);

  if (auto rc = cli::parse_command_line(app, argc, argv)) return *rc;
  auto logger = spdlog::stderr_color_mt("pheromesh");
  logger->set_pattern("%H:%M:%S.%e %^%-5l%$ [%n] %v");
  logger->set_level(spdlog::level::from_str(fd.log_level));
  spdlog::set_default_logger(logger);
  return dispatch(fd, *processes, argc, argv);
}