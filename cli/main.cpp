// pheromesh: the front door. `validate` checks a scenario, `run` launches a
// whole swarm on this host.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>

#include "attach_command.hpp"
#include "bench_lockstep.hpp"
#include "bench_scale.hpp"
#include "bench_soak.hpp"
#include "experiment_command.hpp"
#include "launcher.hpp"
#include "pheromesh/auth/control.hpp"
#include "pheromesh/bus/bus.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/scenario_limits.hpp"
#include "pheromesh/runtime/process.hpp"
#include "replay_command.hpp"
#include "scenario_overrides.hpp"
#include "scenario_paths.hpp"
#include "security_command.hpp"
#include "sim_command.hpp"
#include "sweep_command.hpp"

namespace {

constexpr const char* kRunFooter = R"(FAULTS (--faults, and `fault:` lines in the scenario; docs/faults.md)
  One event per item, items separated by ';':
    kill      TARGETS @TIME                     SIGKILL
    stop      TARGETS @TIME for DURATION        SIGSTOP, then SIGCONT after DURATION
    restart   TARGETS @TIME [for DOWN]          SIGKILL, then start it again after DOWN (default 0 s)
    standby   place:R @TIME                     start one more place agent for region R (--replica N)
    partition TARGETS @TIME for DURATION        cut TARGETS off from every other process
    loss      P% [TARGETS] @TIME for DURATION   drop P % of the packets TARGETS receive (default: all)
  TARGETS  uav:3  uav:0-4  place:1  place:0-3  ground   comma-separated; place:R is the live
           replica of region R with the lowest replica number
  TIME     5s, 2500ms after the swarm was started (realtime runs), or 40t: before tick 40
           (--clock lockstep); DURATION is always wall time (s, ms)
  partition and loss run every process in its own network namespace on a private
  bridge (root needed; --netns-subnet), with the DDS profile `netns`.

Examples:
  pheromesh run scenarios/small-test.textproto --duration 20 --faults "kill uav:3 @5s"
  pheromesh run scenarios/small-test.textproto --duration 20 \
      --faults "stop place:1 @4s for 3s; restart uav:2 @6s for 1s"
  sudo pheromesh run scenarios/small-test.textproto --duration 20 \
      --faults "partition uav:0-1 @4s for 3s; loss 20% @8s for 5s"
  pheromesh run scenarios/small-test.textproto --clock lockstep --ticks 200 --faults "kill uav:1 @40t"

SEVERAL HOSTS (docs/deployment.md)
  Every host runs the same command with its own --host-index, and the same
  $PHEROMESH_CONTROL_KEY (make one with `pheromesh key`). Place agent R runs on
  host R % hosts (a standby on the next host), UAV U on host U % hosts, the
  ground station on --ground-host, which ends the run and writes metrics.json.
    export PHEROMESH_CONTROL_KEY=...      # the same on every host
    pheromesh run scenarios/small-test.textproto --hosts 3 --host-index 0 --dds-profile lan
    pheromesh run scenarios/small-test.textproto --hosts 3 --host-index 1 --dds-profile lan     # on host 1
  Without multicast: --dds-profile lan-unicast --dds-peers 10.0.0.1,10.0.0.2,10.0.0.3
  Watch from anywhere on the LAN: pheromesh attach --dds-profile lan --http 8080
)";

constexpr const char* kAttachFooter = R"(The monitor takes the scenario and the run's options from the swarm's
place agents (published transient-local), so it needs only the domain id and
a DDS profile that reaches the swarm. It conducts nothing and signs no command;
it exits when every place agent finished, writing OUT/metrics.json as seen
from its start (deposit counters are the processes' totals, so the accounting
is complete; coverage and responses count from its start).

Examples:
  pheromesh attach --domain 0 --http 8080                     # a swarm on this host
  pheromesh attach --dds-profile lan --http 8080 --http-bind 0.0.0.0
  pheromesh attach --dds-profile lan-unicast --dds-peers 10.0.0.1,10.0.0.2 --out out/watch
)";

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
  std::printf("%s: OK\n  name        %s\n  map         %d x %d cells, tiles %d x %d of %d cells, %u regions (%d x %d)\n"
              "  obstacles   %zu rectangles\n  targets     %zu\n  uavs        %u\n  run         %u ticks at %.1f Hz, seed %llu\n"
              "  revisit     every %u ticks\n",
              path.c_str(), s->name.c_str(), s->width, s->height, geo.tiles_x(), geo.tiles_y(), s->tile_size,
              geo.region_count(), s->regions_x, s->regions_y, s->obstacles.size(), s->targets.size(), s->uavs, s->ticks,
              s->tick_rate_hz, static_cast<unsigned long long>(s->seed), s->aco.revisit_period);
  std::printf("  policy      %s\n", pheromesh::cli::policy_summary(s.value()).c_str());
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

}  // namespace

int main(int argc, char** argv) {
  using namespace pheromesh;
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
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "Launcher log level")->capture_default_str();

  std::string validate_path;
  auto* v = app.add_subcommand(
      "validate",
      "Check a scenario file; errors name the file, line and field. Also refused: strings that are not UTF-8, and "
      "scenarios beyond the limits on map cells, regions, processes and estimated memory (raise them with "
      "$PHEROMESH_MAX_MAP_CELLS, _REGIONS, _PROCESSES, _PROCESS_MIB, _SWARM_MIB; docs/scenario-format.md)");
  v->add_option("SCENARIO", validate_path, cli::kScenarioArgHelp)
      ->required()
      ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
  cli::OverrideFlags validate_overrides;
  cli::add_override_options(*v, validate_overrides,
                            {cli::FieldFlag::Uavs, cli::FieldFlag::Ticks, cli::FieldFlag::Seed, cli::FieldFlag::Rate});
  v->footer(std::string(cli::kSetFooter) + R"(
Examples:
  pheromesh validate small-test
  pheromesh validate small-test --set swarm.uavs=8 --set shao.aco.alpha=2    prints the overrides it applied)");

  cli::RunOptions ro;
  ro.dds = bus::default_vendor();
  if (const char* p = std::getenv("PHEROMESH_DDS_PROFILE"); p != nullptr && *p != '\0') ro.dds_profile = p;
  auto* r = app.add_subcommand("run", "Run a swarm on this host: one process per place agent and UAV, plus the "
                                      "ground station; writes OUT/metrics.json and OUT/logs/");
  r->add_option("SCENARIO", ro.scenario, cli::kScenarioArgHelp)
      ->required()
      ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
  auto* ticks = cli::add_override_options(
      *r, ro.overrides, {cli::FieldFlag::Uavs, cli::FieldFlag::Ticks, cli::FieldFlag::Seed, cli::FieldFlag::Rate});
  r->add_option("--duration", ro.overrides.duration_s,
                "Seconds to fly instead of --ticks [s]: --set run.ticks=ceil(S x the run's tick rate)")
      ->excludes(ticks);
  r->add_option("--out", ro.out_dir, "Output folder (metrics.json, logs/), relative to the current directory")
      ->capture_default_str();
  r->add_option("--faults", ro.faults_spec,
                "Faults to inject, ';'-separated (added to the scenario's `fault:` lines), e.g. \"kill uav:3 @5s; "
                "stop place:1 @10s for 5s\". See FAULTS below and docs/faults.md");
  r->add_option("--kill", ro.kill_spec,
                "Older form of --faults for kills only: \"uav:3@5s,place:1@2500ms\" = \"kill uav:3 @5s; kill place:1 "
                "@2500ms\"");
  r->add_option("--netns-subnet", ro.netns_subnet,
                "Network faults (partition, loss): the IPv4 subnet of the processes' addresses in their namespaces "
                "(private to this run: nothing of it reaches the host's network)")
      ->capture_default_str();
  r->footer(std::string(kRunFooter) + "\n" + cli::kSetFooter +
            "  pheromesh run small-test --set shao.aco.alpha=2 --uavs 6 --duration 20   the overrides are logged,\n"
            "                                          and every process reads OUT/scenario.textproto\n");
  r->add_option("--dds", ro.dds,
                "DDS vendor of the processes: cyclone, fastdds, or mixed (ground on cyclone; place agents "
                "cyclone/fastdds alternating by index, UAVs fastdds/cyclone), or per role, e.g. "
                "ground=fastdds,place=cyclone,uav=mixed [env PHEROMESH_DDS]")
      ->capture_default_str();
  r->add_flag("--standby", ro.overrides.standby,
              "Run a hot-standby replica of every place agent (place-R.r1): it receives every deposit and keeps the "
              "same field; the primary's output wins through DDS exclusive ownership, and when the primary dies or "
              "stops the standby's takes over within about a liveliness lease (docs/faults.md). Stands for --set "
              "run.standby=true");
  r->add_option("--dds-profile", ro.dds_profile,
                "DDS profile: onehost (loopback, multicast discovery), onehost-unicast, cells (loopback, each process "
                "discovers only those it talks to: a UAV its gateway place agents; for hundreds of UAVs, "
                "docs/dds.md), lan (several hosts, multicast discovery), lan-unicast (several hosts, --dds-peers), "
                "default (vendor defaults) or vendor config files, comma-separated, each process using the one for "
                "its vendor [env PHEROMESH_DDS_PROFILE]")
      ->capture_default_str();
  if (const char* p = std::getenv("PHEROMESH_DDS_PEERS"); p != nullptr) ro.dds_peers = p;
  r->add_option("--dds-peers", ro.dds_peers,
                "lan profiles: every host of the swarm, comma-separated addresses or names (unicast discovery) "
                "[env PHEROMESH_DDS_PEERS]");
  r->add_option("--hosts", ro.hosts,
                "Hosts the swarm is split over; each runs this command with its --host-index "
                "(see SEVERAL HOSTS below)")
      ->check(CLI::Range(1U, 1000U))
      ->capture_default_str();
  r->add_option("--host-index", ro.host_index, "This host's index, 0 .. hosts-1")->capture_default_str();
  r->add_option("--ground-host", ro.ground_host, "The host that runs the ground station (and the web console)")
      ->capture_default_str();
  r->add_option("--domain", ro.domain, "DDS domain id (use distinct ids for swarms sharing a host)")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  r->add_option("--clock", ro.clock,
                "realtime (every process on its own clock) or lockstep (numbered ticks conducted by the ground "
                "station; same numbers as `pheromesh sim`)")
      ->check(CLI::IsMember({"realtime", "lockstep"}))
      ->capture_default_str();
  r->add_option("--process-log-level", ro.log_level, "Log level of the spawned processes")->capture_default_str();
  r->add_option("--lease-ms", ro.lease_ms,
                "Liveliness lease of every process [ms]: how fast a dead process is noticed; raise it on an "
                "overloaded host, where a stalled process can miss a short lease and be reported lost")
      ->check(CLI::Range(50, 60000))
      ->capture_default_str();
  r->add_flag("--discovery-server", ro.discovery_server,
              "Fast DDS only (--dds fastdds): start a Fast DDS discovery server (fast-discovery-server, port 11811 + "
              "domain) and let every process discover through it instead of with every other process; measured to "
              "cut discovery traffic tenfold at 100 UAVs (README, Scale)");
  r->add_option("--start-rate", ro.start_rate,
                "UAV processes started per second in swarms of more than 64 processes (0: all at once): every new "
                "process is discovered by every other one, and hundreds at once flood a small host")
      ->check(CLI::Range(0.0, 10000.0))
      ->capture_default_str();
  r->add_option("--progress", ro.progress_s, "Seconds between the ground station's progress lines")->capture_default_str();
  r->add_option("--start-timeout", ro.start_timeout_s,
                "Lockstep: how long the conductor waits before tick 0 for every process to report ready; past it the "
                "run is refused (exit 1) rather than run without them [s] (default: 60 s + 1 s per process)")
      ->check(CLI::Range(1.0, 86400.0));
  r->add_option("--http", ro.http_port,
                "Serve the web console on this port (e.g. 8080) and print its URL; it records the run to "
                "OUT/console.phrec for `pheromesh replay`");
  r->add_option("--http-bind", ro.http_bind, "Address the console listens on (0.0.0.0: every interface)")
      ->capture_default_str();
  if (const char* p = std::getenv("PHEROMESH_SECURE"); p != nullptr) ro.secure = p;
  r->add_option("--secure", ro.secure,
                "DDS Security: the directory made by `pheromesh security init` for this swarm; every process "
                "authenticates with its own identity there, and the permissions, access control and the "
                "governance's encryption apply (docs/security.md) [env PHEROMESH_SECURE]");
  r->add_option("--record", ro.record, "Where the console records the run (default OUT/console.phrec)");
  r->add_flag("--no-record", ro.no_record, "Do not record the console");

  cli::SimOptions so;
  auto* sim = app.add_subcommand("sim", "Run the whole swarm in this process, deterministically (no DDS): the same "
                                        "core code and lockstep schedule as `run --clock lockstep`, the same "
                                        "OUT/metrics.json and OUT/final_field.txt");
  sim->add_option("SCENARIO", so.scenario, cli::kScenarioArgHelp)
      ->required()
      ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
  cli::add_override_options(*sim, so.overrides, {cli::FieldFlag::Seed, cli::FieldFlag::Ticks, cli::FieldFlag::Uavs});
  sim->add_option("--out", so.out_dir, "Output folder, relative to the current directory")->capture_default_str();
  sim->add_flag("--quiet", so.quiet, "No progress lines");
  sim->add_option("--faults", so.faults,
                  "Fault schedule timed in ticks, e.g. \"kill uav:3 @40t; kill place:1 @60t\" (docs/faults.md); "
                  "stop, partition and loss do not change simulated numbers");
  sim->add_flag("--standby", so.overrides.standby,
                "Every place agent has a standby that takes over when it is killed; stands for --set "
                "run.standby=true");
  sim->footer(std::string(cli::kSetFooter) + R"(
Examples:
  pheromesh sim small-test --ticks 100 --out out/sim
  pheromesh sim small-test --set shao.aco.alpha=2 --set swarm.uavs=8 --seed 3)");

  cli::SweepOptions swo;
  auto* sw = app.add_subcommand(
      "sweep", "Run a scenario on the in-process simulator for every combination of parameter values (--set "
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
  sw->add_option("--domain", swo.domain, "With --distributed: the DDS domain of the processes (0: the launcher's)")
      ->check(CLI::Range(0U, 232U));
  sw->footer(std::string(cli::kSweepFooter) + "\n" + cli::kSetFooter);

  cli::ExperimentOptions eo;
  auto* ex = app.add_subcommand("experiment", "Run one of the papers' experiments as Monte Carlo with the simulator and "
                                              "write a report (Markdown + CSV + SVG) with our numbers beside the paper's");
  ex->add_option("NAME", eo.name, "Experiment (see --list)");
  ex->add_flag("--list", eo.list, "List the experiments and our verdict on each paper claim");
  ex->add_flag("--all", eo.all,
               "Run every experiment (each with --runs or its paper's count) and write OUT/summary.md: every paper "
               "figure beside ours with its verdict, the variants' gains and the wall times (OUT: --out, default "
               "out/experiments)");
  ex->add_option("--runs", eo.runs, "Monte Carlo runs (default: the paper's count)");
  ex->add_option("--out", eo.out_dir, "Output folder (default out/experiments/NAME)");
  ex->add_flag("--distributed", eo.distributed,
               "Also fly each run of the Monte Carlo as real processes (pheromesh run --clock lockstep) and check "
               "that its numbers equal the simulator's for the same seed; use a small --runs");
  ex->add_option("--dds", eo.dds, "With --distributed: the vendor(s) of the processes (cyclone, fastdds, mixed)")
      ->capture_default_str();
  ex->add_option("--domain", eo.domain, "With --distributed: the DDS domain of the processes (0: the launcher's)");
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

  cli::ReplayOptions rpo;
  auto* rp = app.add_subcommand("replay", "Serve the web console from a recording (OUT/console.phrec of `run --http`), "
                                          "with a time slider");
  rp->add_option("FILE", rpo.file, "Recording")->required()->check(CLI::ExistingFile);
  rp->add_option("--http", rpo.port, "Port of the console (0: any free port)")->capture_default_str();
  rp->add_option("--http-bind", rpo.bind, "Address the console listens on")->capture_default_str();
  rp->add_flag("--check", rpo.check, "Only read the recording and say what it holds");

  cli::BenchScaleOptions bso;
  auto* bench = app.add_subcommand("bench", "Benchmarks of whole swarms (they print figures; they are not tests)");
  bench->require_subcommand(1);
  auto* bs = bench->add_subcommand(
      "scale", "Run `pheromesh run` with swarms of increasing size, per DDS vendor, and tabulate what each size costs: "
               "late ticks, discovery time, CPU per UAV tick, memory (PSS/RSS) and threads per process, UDP datagrams "
               "per UAV tick");
  bs->add_option("SCENARIO", bso.scenario, "Scenario file, e.g. scenarios/scale-100x100.textproto (its start area "
                                           "must hold the largest size)")
      ->required()
      ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
  bs->add_option("--sizes", bso.sizes, "UAV counts to run, comma-separated")->capture_default_str();
  bs->add_option("--max", bso.max_uavs, "Leave out the sizes above this many UAVs (0: none)")->capture_default_str();
  bs->add_option("--dds", bso.dds, "Vendors, comma-separated among cyclone, fastdds, mixed: each size runs once per vendor")
      ->capture_default_str();
  bs->add_option("--rate", bso.rate_hz, "Tick rate of every process [Hz]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  bs->add_option("--ticks", bso.ticks, "Ticks each UAV flies")->check(CLI::Range(1U, 1000000U))->capture_default_str();
  bs->add_option("--lease-ms", bso.lease_ms, "Liveliness lease of every process [ms] (generous: a loaded host stalls)")
      ->check(CLI::Range(50, 60000))
      ->capture_default_str();
  bs->add_option("--out", bso.out_dir, "Output folder: scale.md/.csv/.json, *.svg, and one folder V-N per run")
      ->capture_default_str();
  bs->add_option("--stop-late-share", bso.stop_late_share,
                 "Once a size has more than this share of late UAV ticks, skip the vendor's larger sizes")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  bs->add_option("--domain", bso.domain, "DDS domain id of the runs")->check(CLI::Range(0, 232))->capture_default_str();
  bs->add_option("--extra", bso.extra, "More arguments for `pheromesh run`, in one string, e.g. \"--dds-profile default\"");
  bs->footer(cli::kBenchScaleFooter);

  cli::BenchLockstepOptions blo;
  auto* bl = bench->add_subcommand(
      "lockstep",
      "Where a lockstep tick's time goes: ticks/s and the time of each UAV and place phase of `pheromesh run "
      "--clock lockstep`, per swarm and DDS vendor, against the in-process simulator and the round trip of "
      "one sample between two processes, all measured in one run");
  bl->add_option("--swarms", blo.swarms,
                 "SCENARIO[:UAVS] entries, comma-separated (a shipped scenario's name or a path; UAVS sets swarm.uavs)")
      ->capture_default_str();
  bl->add_option("--dds", blo.dds, "Vendors, comma-separated among cyclone, fastdds, mixed")->capture_default_str();
  bl->add_option("--ticks", blo.ticks, "Lockstep ticks per run (sets run.ticks)")
      ->check(CLI::Range(1U, 100000U))
      ->capture_default_str();
  bl->add_option("--pings", blo.pings, "Round trips per vendor pairing for the floor")
      ->check(CLI::Range(10U, 100000U))
      ->capture_default_str();
  bl->add_option("--domain", blo.domain, "DDS domain of the runs (the floor uses the next one)")
      ->check(CLI::Range(0, 231))
      ->capture_default_str();
  bl->add_option("--out", blo.out_dir, "Output folder: lockstep.md, lockstep.json, one folder per swarm and run")
      ->capture_default_str();
  bl->add_option("--baseline", blo.baseline,
                 "Another build's pheromesh (e.g. of the commit before a change): each run is flown with it too and the "
                 "two compared by wall time");
  bl->footer(cli::kBenchLockstepFooter);
  cli::LockstepEchoOptions leo;
  auto* le = bench->add_subcommand("lockstep-echo", "The other end of bench lockstep's floor measurement");
  le->group("");  // hidden: bench lockstep starts it
  le->add_option("--dds", leo.dds)->check(CLI::IsMember({"cyclone", "fastdds"}));
  le->add_option("--domain", leo.domain)->check(CLI::Range(0, 232));

  cli::BenchSoakOptions bko;
  auto* bk = bench->add_subcommand(
      "soak", "Run one swarm for a long time with a fault every so often, and report the RSS, open file descriptors "
              "and threads of every role (uav, place, ground, launcher) over time, with growth per hour");
  bk->add_option("SCENARIO", bko.scenario, cli::kScenarioArgHelp)
      ->required()
      ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
  bk->add_option("--processes", bko.processes, "UAVs + place agents + the ground station (the UAVs fill the rest)")
      ->check(CLI::Range(3U, 5000U))
      ->capture_default_str();
  bk->add_option("--duration", bko.duration, "How long the swarm runs: 1h, 10m, 90s")->capture_default_str();
  bk->add_option("--fault-every", bko.fault_every, "One fault per period (0: none)")->capture_default_str();
  bk->add_option("--sample-every", bko.sample_every, "Sampling period of /proc")->capture_default_str();
  bk->add_option("--warmup", bko.warmup, "Samples before this are left out of the growth fits")->capture_default_str();
  bk->add_option("--rate", bko.rate_hz, "Tick rate of every process [Hz]")->check(CLI::PositiveNumber)->capture_default_str();
  bk->add_option("--lease-ms", bko.lease_ms, "Liveliness lease [ms] (generous: a loaded host stalls)")
      ->check(CLI::Range(50, 60000))
      ->capture_default_str();
  bk->add_option("--dds", bko.dds, "DDS vendor(s) as `pheromesh run --dds` takes them")->capture_default_str();
  bk->add_option("--domain", bko.domain, "DDS domain id of the run")->check(CLI::Range(0, 232))->capture_default_str();
  bk->add_option("--out", bko.out_dir, "Output folder: soak.md, soak.csv, soak-processes.csv, run/")->capture_default_str();
  bk->add_option("--extra", bko.extra, "More arguments for `pheromesh run`, in one string");
  bk->footer(cli::kBenchSoakFooter);

  auto* key = app.add_subcommand("key",
                                 "Print a new random control key (64 hex digits) for $PHEROMESH_CONTROL_KEY: "
                                 "every host of a swarm over several hosts exports the same one");

  cli::AttachOptions ao;
  ao.dds = bus::default_vendor();
  if (const char* p = std::getenv("PHEROMESH_DDS_PROFILE"); p != nullptr && *p != '\0') ao.dds_profile = p;
  if (const char* p = std::getenv("PHEROMESH_DDS_PEERS"); p != nullptr) ao.dds_peers = p;
  auto* at = app.add_subcommand("attach",
                                "Monitor a running swarm from this host, found by its domain id alone: "
                                "progress lines, metrics, and with --http the web console");
  at->add_option("--domain", ao.domain, "DDS domain id of the swarm")->check(CLI::Range(0, 232))->capture_default_str();
  at->add_option("--dds", ao.dds, "DDS vendor of the monitor: cyclone or fastdds (either reaches any swarm)")
      ->capture_default_str();
  at->add_option(
        "--dds-profile", ao.dds_profile,
        "DDS profile that reaches the swarm: onehost (same host), lan, lan-unicast (with --dds-peers), or files")
      ->capture_default_str();
  at->add_option("--dds-peers", ao.dds_peers,
                 "lan profiles: the swarm's hosts, comma-separated [env PHEROMESH_DDS_PEERS]");
  at->add_option("--out", ao.out_dir, "Output folder (metrics.json, console recording)")->capture_default_str();
  at->add_option("--http", ao.http_port, "Serve the web console on this port (0: any free port)");
  at->add_option("--http-bind", ao.http_bind, "Address the console listens on (0.0.0.0: every interface)")
      ->capture_default_str();
  at->add_option("--record", ao.record, "Record the console to this file (for pheromesh replay)");
  at->add_option("--timeout", ao.timeout_s, "Longest wait for a running swarm [s]")->capture_default_str();
  at->add_option("--progress", ao.progress_s, "Seconds between progress lines")->capture_default_str();
  at->add_option("--process-log-level", ao.log_level, "Log level of the monitor")->capture_default_str();
  if (const char* p = std::getenv("PHEROMESH_SECURE"); p != nullptr) ao.secure = p;
  at->add_option("--secure", ao.secure,
                 "DDS Security: the swarm's directory of `pheromesh security init`; the monitor authenticates with "
                 "its read-only identity 'monitor' there (docs/security.md) [env PHEROMESH_SECURE]");
  at->footer(kAttachFooter);

  cli::SecurityInitOptions sio;
  auto* sec = app.add_subcommand("security", "DDS Security for a swarm: authentication, access control, encryption "
                                             "(docs/security.md)");
  sec->require_subcommand(1);
  auto* si = sec->add_subcommand("init", "Make a swarm's CA, one identity per process (UAVs, place agents, ground "
                                         "station, read-only monitor), the governance and the signed permissions "
                                         "in DIR, for `pheromesh run --secure DIR`");
  si->add_option("DIR", sio.dir, "Directory to make (mode 0700)")->required();
  si->add_option("--scenario", sio.scenario, "The swarm's scenario: its UAVs, regions and standby setting")
      ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
  si->add_option("--uavs", sio.uavs, "UAV identities to make (default: the scenario's swarm.uavs)");
  si->add_option("--regions", sio.regions, "Place-agent identities to make (default: the scenario's regions)");
  si->add_flag("--standby", sio.standby, "Also an identity for each place agent's standby (place-R.r1)");
  si->add_option("--probes", sio.probes, "Also identities probe-0 .. probe-N-1 for pheromesh-test-probe and benches");
  si->add_option("--protection", sio.protection,
                 "What the governance does to the traffic: encrypt (AES-GCM), sign (GMAC, readable) or none "
                 "(authentication and access control only)")
      ->check(CLI::IsMember({"encrypt", "sign", "none"}))
      ->capture_default_str();
  si->add_option("--days", sio.days, "Validity of the certificates and permissions [days]")->capture_default_str();
  si->add_flag("--force", sio.force, "Replace the files of an earlier `security init` in DIR");
  si->footer(cli::kSecurityFooter);

  CLI11_PARSE(app, argc, argv);
  auto logger = spdlog::stderr_color_mt("pheromesh");
  logger->set_pattern("%H:%M:%S.%e %^%-5l%$ [%n] %v");
  logger->set_level(spdlog::level::from_str(log_level));
  spdlog::set_default_logger(logger);

  // Every command inside one try: an exception that escapes one (a policy
  // plugin's code may throw from any step, docs/writing-a-policy.md) is
  // reported and gives exit 4, never an abort without a message.
  try {
    if (v->parsed()) return validate(validate_path, validate_overrides);
    if (key->parsed()) {
      std::printf("%s\n", auth::random_control_key_hex().c_str());
      return 0;
    }
    if (at->parsed()) return cli::run_attach(ao);
    if (si->parsed()) return cli::run_security_init(sio);
    if (sim->parsed()) return cli::run_sim(so);
    if (ex->parsed()) return cli::run_experiment_command(eo);
    if (sw->parsed()) {
      swo.command = cli::command_line(argc, argv);
      return cli::run_sweep(swo);
    }
    if (rp->parsed()) return cli::run_replay(rpo);
    if (bs->parsed()) return cli::run_bench_scale(bso);
    if (bl->parsed() || le->parsed()) {
      runtime::install_shutdown_handlers();
      return bl->parsed() ? cli::run_bench_lockstep(blo) : cli::run_lockstep_echo(leo);
    }
    if (bk->parsed()) return cli::run_bench_soak(bko);
    return cli::Launcher(ro).run();
  } catch (const std::exception& e) {
    spdlog::critical("fatal: {}", e.what());
    return 4;
  }
}
