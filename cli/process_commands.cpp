// `run`, `attach`, `cell`, `bench`, `security` and `replay` (process_commands.hpp):
// the subcommands of a full build.
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdlib>

#include "bench/commands/bench_floor.hpp"
#include "bench/commands/bench_lockstep.hpp"
#include "bench/commands/bench_scale.hpp"
#include "bench/commands/bench_soak.hpp"
#include "bench/commands/bench_start.hpp"
#include "launch/attach_command.hpp"
#include "launch/cell_command.hpp"
#include "launch/launcher.hpp"
#include "pheromesh/bus/bus.hpp"
#include "pheromesh/cliutil/command_line.hpp"
#include "pheromesh/cliutil/scenario_paths.hpp"
#include "pheromesh/console/mavlink_feed.hpp"
#include "pheromesh/runtime/process.hpp"
#include "process_commands.hpp"
#include "replay_command.hpp"
#include "scenario_overrides.hpp"
#include "security_command.hpp"

namespace pheromesh::cli {

namespace {

// --mavlink and --mavlink-rate-hz of `run`, `attach` and `replay`, checked
// as the ground station checks them (console/mavlink_feed.hpp). `source`:
// what is streamed; `commands`: what the stream takes from the station.
void add_mavlink_options(CLI::App* c, std::string& target, double& rate_hz, const std::string& source,
                         const std::string& commands) {
  const std::string stream = "Stream " + source +
                             " to a MAVLink ground-control station at udp:HOST:PORT (QGroundControl: "
                             "udp:127.0.0.1:14550): UAVs 0..249 as vehicles 1..250, every UAV as ADS-B traffic, the "
                             "ground station as system 251 with place-agent losses and found targets; ";
  c->add_option("--mavlink", target, stream + commands + " (docs/mavlink.md)")->check([](const std::string& v) {
    const auto t = console::parse_mavlink_target(v, "");
    return t ? std::string() : t.error().message;
  });
  c->add_option("--mavlink-rate-hz", rate_hz,
                "With --mavlink: position, attitude and ADS-B reports per UAV per second [Hz], 0.2..20 (heartbeats "
                "at 1 Hz)")
      ->capture_default_str()
      ->check([](const std::string& v) {
        char* end = nullptr;
        const double hz = std::strtod(v.c_str(), &end);
        if (end == v.c_str() || *end != '\0') return v + ": not a number";
        const auto r = console::check_mavlink_rate(hz, "");
        return r ? std::string() : r.error().message;
      });
}

constexpr const char* kHostsFileHelp =
    "The swarm's hosts in a file, one per line in host-index order: an IPv4 address or a name that resolves to one "
    "address; '#' starts a comment, blank lines are skipped. It stands for --hosts (its number of entries) and "
    "--dds-peers (its entries), which must then be left out, $PHEROMESH_DDS_PEERS too; --host-index, left out, is "
    "the one entry that is an address of this host (docs/deployment.md)";

// Where --dds-peers came from, for a hosts file's refusal of it.
std::string peers_from(const CLI::App& c, const std::string& peers) {
  if (c.count("--dds-peers") > 0) return "--dds-peers";
  return peers.empty() ? "" : "$PHEROMESH_DDS_PEERS";
}

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
  host R % hosts (a standby on the next host), each UAV on the host of its home
  place agent (UAV U: place agent U % regions), the ground station on
  --ground-host, which ends the run and writes metrics.json. In cells (the
  default) --dds-peers lists every host's address in host-index order:
    export PHEROMESH_CONTROL_KEY=...      # the same on every host
    pheromesh run scenarios/small-test.textproto --hosts 3 --host-index 0 --dds-peers 10.0.0.1,10.0.0.2,10.0.0.3
    pheromesh run scenarios/small-test.textproto --hosts 3 --host-index 1 --dds-peers 10.0.0.1,10.0.0.2,10.0.0.3
  Or the same list in a file, one host per line (# comments), the index found by this host's address:
    pheromesh run scenarios/small-test.textproto --hosts-file hosts.txt
  A UAV may fly elsewhere: --pin-uavs 0-9=2,12=0 (UAV ids = host index, the same on every host).
  Flat discovery instead: --dds-profile lan (multicast) or lan-unicast --dds-peers ...
  Watch from anywhere on the LAN: pheromesh attach --dds-peers 10.0.0.1,10.0.0.2,10.0.0.3 --http 8080
)";

constexpr const char* kAttachFooter = R"(The monitor takes the scenario and the run's options from the swarm's
place agents (published transient-local), so it needs only the domain id and
a DDS profile that reaches the swarm. It conducts nothing and signs no command;
it exits when every place agent finished, writing OUT/metrics.json as seen
from its start (deposit counters are the processes' totals, so the accounting
is complete; coverage and responses count from its start).

Examples:
  pheromesh attach --domain 0 --http 8080                     # a swarm on this host (in cells, the default)
  pheromesh attach --dds-peers 10.0.0.1,10.0.0.2,10.0.0.3     # a swarm in cells over these hosts
  pheromesh attach --domain 0 --cell-hubs 17                  # as `pheromesh run` prints it: names fewer hubs
  pheromesh attach --dds-profile lan --http 8080 --http-bind 0.0.0.0      # a swarm with flat discovery
  pheromesh attach --dds-profile lan-unicast --dds-peers 10.0.0.1,10.0.0.2 --out out/watch
)";


class FullCommands final : public ProcessCommands {
 public:
  explicit FullCommands(CLI::App& app) { add(app); }

  std::optional<int> run_parsed() override {
    if (at->parsed()) {
      ao.dds_peers_from = peers_from(*at, ao.dds_peers);
      return run_attach(ao);
    }
    if (ce->parsed()) return run_cell_command(co);
    if (si->parsed()) return run_security_init(sio);
    if (rp->parsed()) return run_replay(rpo);
    if (bs->parsed()) return run_bench_scale(bso);
    if (bl->parsed() || le->parsed()) {
      runtime::install_shutdown_handlers();
      return bl->parsed() ? run_bench_lockstep(blo) : run_lockstep_echo(leo);
    }
    if (bk->parsed()) return run_bench_soak(bko);
    if (bt->parsed()) {
      bto.programs_dir = executable_dir();
      return run_bench_start(bto);
    }
    if (!r->parsed()) return std::nullopt;
    // A hosts file refuses --hosts and --dds-peers beside it and picks the index itself.
    ro.hosts_given = r->count("--hosts") > 0;
    ro.host_index_given = r->count("--host-index") > 0;
    ro.dds_peers_from = peers_from(*r, ro.dds_peers);
    try {
      return Launcher(ro).run();
    } catch (const std::exception& e) {
      spdlog::critical("fatal: {}", e.what());
      return 4;
    }
  }

 private:
  RunOptions ro;
  ReplayOptions rpo;
  BenchScaleOptions bso;
  BenchLockstepOptions blo;
  LockstepEchoOptions leo;
  BenchSoakOptions bko;
  BenchStartOptions bto;
  AttachOptions ao;
  SecurityInitOptions sio;
  CellCommandOptions co;
  CLI::App *r = nullptr, *rp = nullptr, *bs = nullptr, *bl = nullptr, *le = nullptr, *bk = nullptr, *bt = nullptr,
           *at = nullptr, *si = nullptr, *ce = nullptr;

  void add(CLI::App& app) {
    add_run(app);
    add_replay(app);
    add_bench(app);
    add_attach(app);
    ce = add_cell_command(app, co);
    add_security(app);
  }

  // `pheromesh run`: its flags by group, in the order --help lists them.
  void add_run(CLI::App& app) {
    ro.dds = bus::default_vendor();
    if (const char* p = std::getenv("PHEROMESH_DDS_PROFILE"); p != nullptr && *p != '\0') ro.dds_profile = p;
    r = app.add_subcommand("run", "Run a swarm on this host: one process per place agent and UAV, plus the "
                                        "ground station; writes OUT/metrics.json, series.csv, final_field.txt/.csv "
                                        "(docs/outputs.md) and OUT/logs/");
    r->add_option("SCENARIO", ro.scenario, cli::kScenarioArgHelp)
        ->required()
        ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
    auto* ticks = cli::add_override_options(
        *r, ro.overrides, {cli::FieldFlag::Uavs, cli::FieldFlag::Ticks, cli::FieldFlag::Seed, cli::FieldFlag::Rate});
    r->add_option("--duration", ro.overrides.duration_s,
                  "How long to fly instead of --ticks: a number with an optional unit ms, s, m or h (plain: seconds), "
                  "e.g. 20, 90s, 10m; --set run.ticks=ceil(seconds x the run's tick rate)")
        ->transform(cli::duration_validator(/*to_seconds=*/true))
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
    add_run_middleware();
    add_run_hosts_and_clock();
    add_run_console();
  }

  // run: the DDS vendor, profile and peers; --strict, --standby.
  void add_run_middleware() {
    r->add_option("--dds", ro.dds,
                  "DDS vendor of the processes: cyclone, fastdds, or mixed (ground on cyclone; place agents "
                  "cyclone/fastdds alternating by index, UAVs fastdds/cyclone), or per role, e.g. "
                  "ground=fastdds,place=cyclone,uav=mixed [env PHEROMESH_DDS]")
        ->capture_default_str();
    r->add_flag("--strict", ro.strict,
                "Fail the run (exit 9) if a UAV's state was refused as implausible: its policy moved further in a "
                "tick than its max_step allows (docs/writing-a-policy.md)");
    r->add_flag("--standby", ro.overrides.standby,
                "Run a hot-standby replica of every place agent (place-R.r1): it receives every deposit and keeps the "
                "same field; the primary's output wins through DDS exclusive ownership, and when the primary dies or "
                "stops the standby's takes over within about a liveliness lease (docs/faults.md). Stands for --set "
                "run.standby=true");
    r->add_option("--dds-profile", ro.dds_profile,
                  "DDS profile: cells (the default: each process discovers only those it talks to, a UAV its gateway "
                  "place agents; on one host, or over several with --dds-peers; docs/dds.md), or flat discovery: "
                  "onehost (loopback, multicast), onehost-unicast, lan (several hosts, multicast), lan-unicast "
                  "(several hosts, --dds-peers), default (vendor defaults) or vendor config files, comma-separated, "
                  "each process using the one for its vendor. Without it: cells, but partition and loss faults take "
                  "netns, --discovery-server onehost, and a one-host run on a domain above 100 onehost, each with a "
                  "note [env PHEROMESH_DDS_PROFILE]");
    if (const char* p = std::getenv("PHEROMESH_DDS_PEERS"); p != nullptr) ro.dds_peers = p;
    r->add_option("--dds-peers", ro.dds_peers,
                  "Every host of the swarm, comma-separated addresses or names: in cells one per host in --host-index "
                  "order; lan-unicast: unicast discovery peers [env PHEROMESH_DDS_PEERS]");
  }

  // run: several hosts, the domain, the clock, and how the processes start.
  void add_run_hosts_and_clock() {
    r->add_option("--hosts", ro.hosts,
                  "Hosts the swarm is split over; each runs this command with its --host-index "
                  "(see SEVERAL HOSTS below)")
        ->check(CLI::Range(1U, 1000U))
        ->capture_default_str();
    r->add_option("--host-index", ro.host_index,
                  "This host's index, 0 .. hosts-1; with --hosts-file, left out: the one entry that is an address "
                  "of this host")
        ->capture_default_str();
    r->add_option("--hosts-file", ro.hosts_file, kHostsFileHelp)->check(CLI::ExistingFile);
    r->add_option("--ground-host", ro.ground_host, "The host that runs the ground station (and the web console)")
        ->capture_default_str();
    r->add_option("--pin-uavs", ro.pin_uavs,
                  "With --hosts: UAVs that fly on a host of your choosing instead of beside their home place agent, "
                  "U=H or A-B=H, comma-separated (e.g. 0-9=2,12=0); the same on every host");
    r->add_option("--domain", ro.domain, "DDS domain id (use distinct ids for swarms sharing a host)")
        ->check(CLI::Range(0, 232))
        ->capture_default_str();
    r->add_option("--clock", ro.clock,
                  "realtime (every process on its own clock) or lockstep (numbered ticks conducted by the ground "
                  "station; same numbers as `pheromesh sim`)")
        ->check(CLI::IsMember({"realtime", "lockstep"}))
        ->capture_default_str();
    r->add_option("--process-log-level", ro.log_level,
                  "Log level of the spawned processes: trace, debug, info, warn, error, critical or off")
        ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
        ->capture_default_str();
    r->add_option("--lease-ms", ro.lease_ms,
                  "Liveliness lease of every process [ms]: how fast a dead process is noticed; raise it on an "
                  "overloaded host, where a stalled process can miss a short lease and be reported lost. Default: "
                  "1000, or 5000 when this host starts more than 150 processes (their discovery stalls them)")
        ->check(CLI::Range(50, 60000));
    r->add_flag("--discovery-server", ro.discovery_server,
                "Fast DDS only (--dds fastdds): start a Fast DDS discovery server (fast-discovery-server, port 11811 + "
                "domain) and let every process discover through it instead of with every other process; measured to "
                "cut discovery traffic tenfold at 100 UAVs (README, Scale)");
    r->add_option("--start-rate", ro.start_rate,
                  "UAV processes started per second in swarms of more than 64 processes (0: all at once): every new "
                  "process is discovered by every other one, and hundreds at once flood a small host")
        ->check(CLI::Range(0.0, 10000.0))
        ->capture_default_str();
  }

  // run: progress, the start timeout, the web console, security, the recording, tracks and MAVLink.
  void add_run_console() {
    r->add_option("--progress", ro.progress_s, "Seconds between the ground station's progress lines [s], > 0")
        ->check(CLI::Range(0.01, 86400.0))
        ->capture_default_str();
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
    r->add_flag("--tracks", ro.tracks,
                "The ground station also writes OUT/tracks.csv: every UAV state it heard (docs/outputs.md)");
    add_mavlink_options(r, ro.mavlink, ro.mavlink_rate_hz, "the swarm",
                        "it takes pause, continue and stop signed with the swarm's MAVLink key, which the ground "
                        "station writes to OUT/mavlink.key");
  }

  void add_replay(CLI::App& app) {
    rp = app.add_subcommand("replay",
                            "Serve the web console from a recording (OUT/console.phrec of `run --http`), "
                            "with a time slider; with --mavlink, also stream it to a MAVLink "
                            "ground-control station as the live run was streamed");
    rp->add_option("FILE", rpo.file, "Recording")->required()->check(CLI::ExistingFile);
    rp->add_option("--http", rpo.port, "Port of the console (0: any free port)")->capture_default_str();
    rp->add_option("--http-bind", rpo.bind, "Address the console listens on")->capture_default_str();
    rp->add_flag("--check", rpo.check, "Only read the recording and say what it holds");
    add_mavlink_options(rp, rpo.mavlink, rpo.mavlink_rate_hz,
                        "the recording, from its first frame at the pace it was recorded (its last state is held at "
                        "the end),",
                        "a station's pause and continue (unsigned: a replay holds no key) pause and continue the "
                        "playback; disarm and every other command get COMMAND_ACK UNSUPPORTED");
  }

  void add_bench(CLI::App& app) {
    auto* bench = app.add_subcommand("bench", "Benchmarks of whole swarms (they print figures; they are not tests)");
    bench->require_subcommand(1);
    add_bench_scale(*bench);
    add_bench_lockstep(*bench);
    add_bench_soak(*bench);
    add_bench_start(*bench);
  }

  void add_bench_start(CLI::App& bench) {
    bt = bench.add_subcommand("start",
                              "What a UAV process costs to start: the CPU of this build's pheromesh-uav "
                              "started alone, again and again, against a process that does nothing");
    bt->add_option("SCENARIO", bto.scenario, "Scenario of the UAVs started alone, e.g. scale-100x100")
        ->required()
        ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
    bt->add_option("--dds", bto.dds, "Vendors, comma-separated among cyclone, fastdds: one row each")
        ->delimiter(',')
        ->check(CLI::IsMember({"cyclone", "fastdds"}))
        ->capture_default_str();
    bt->add_option("--runs", bto.runs, "Starts of each kind")->check(CLI::Range(1U, 10000U))->capture_default_str();
    bt->add_option("--domain", bto.domain, "DDS domain of the UAVs started alone")
        ->check(CLI::Range(0, 232))
        ->capture_default_str();
    bt->add_option("--baseline", bto.baseline,
                   "Another build's bin folder (e.g. of the commit before a change): its pheromesh-uav runs too, "
                   "alternating with this build's")
        ->check(CLI::ExistingDirectory);
    bt->add_option("--wait", bto.wait_s,
                   "Seconds a UAV of the waiting rows waits for a start that does not come (0: no waiting rows, else "
                   "at least 3: the CPU is read from 1.5 s to 0.5 s before the end); each such start takes this long")
        ->check(CLI::Validator(
            [](const std::string& v) -> std::string {
              double w = -1;
              std::size_t used = 0;
              try {
                w = std::stod(v, &used);
              } catch (const std::exception&) {
                used = 0;
              }
              const bool ok = used == v.size() && (w == 0 || (w >= 3 && w <= 600));
              return ok ? std::string() : "0 (no waiting rows) or 3 to 600 s, got '" + v + "'";
            },
            "0 or 3..600"))
        ->capture_default_str();
    bt->footer(cli::kBenchStartFooter);
  }

  void add_bench_scale(CLI::App& bench) {
    bs = bench.add_subcommand(
        "scale",
        "Run `pheromesh run` with swarms of increasing size, per DDS vendor, and tabulate what each size costs: "
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
    bs->add_option("--repeat", bso.repeat,
                   "Runs of each size and vendor; the summary holds a size only if every run held it (the worst run)")
        ->check(CLI::Range(1U, 100U))
        ->capture_default_str();
    bs->add_option("--stop-late-share", bso.stop_late_share,
                   "Once a size has more than this share of late UAV ticks, skip the vendor's larger sizes")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    bs->add_option("--domain", bso.domain, "DDS domain id of the runs")->check(CLI::Range(0, 232))->capture_default_str();
    bs->add_option("--extra", bso.extra, "More arguments for `pheromesh run`, in one string, e.g. \"--dds-profile default\"");
    bs->add_option("--floor-pings", bso.floor_pings,
                   "Round trips per vendor for the floor, before the runs (0: no floor)")
        ->check(CLI::Range(0U, 100000U))
        ->capture_default_str();
    bs->add_option("--floor-view-bytes", bso.floor_view_bytes, "Payload of the floor's sample down (a UAV's view) [B]")
        ->check(CLI::Range(0U, 32768U))
        ->capture_default_str();
    bs->add_option("--floor-uplink-bytes", bso.floor_uplink_bytes,
                   "Payload of the floor's sample up (a UAV's state with its deposits) [B]")
        ->check(CLI::Range(0U, 32768U))
        ->capture_default_str();
    bs->footer(cli::kBenchScaleFooter);
  }

  void add_bench_lockstep(CLI::App& bench) {
    bl = bench.add_subcommand(
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
    bl->add_option("--repeat", blo.repeat,
                   "Runs per swarm, vendor and build; with --baseline the builds alternate, each going first every "
                   "other round. The report adds the median and the range of ticks/s and of this build's paired "
                   "ratio to the baseline (one run moves by ±20 % on a busy 2-core host)")
        ->check(CLI::Range(1U, 50U))
        ->capture_default_str();
    bl->footer(cli::kBenchLockstepFooter);
    le = bench.add_subcommand("lockstep-echo", "The other end of bench lockstep's floor measurement");
    le->group("");  // hidden: bench lockstep starts it
    le->add_option("--dds", leo.dds)->check(CLI::IsMember({"cyclone", "fastdds"}));
    le->add_option("--domain", leo.domain)->check(CLI::Range(0, 232));
    le->add_option("--answer-bytes", leo.answer_bytes)->check(CLI::Range(0U, 32768U));
  }

  void add_bench_soak(CLI::App& bench) {
    bk = bench.add_subcommand(
        "soak",
        "Run one swarm for a long time with a fault every so often, and report the RSS, open file descriptors "
        "and threads of every role (uav, place, ground, launcher) over time, with growth per hour");
    bk->add_option("SCENARIO", bko.scenario, cli::kScenarioArgHelp)
        ->required()
        ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
    bk->add_option("--processes", bko.processes, "UAVs + place agents + the ground station (the UAVs fill the rest)")
        ->check(CLI::Range(3U, 5000U))
        ->capture_default_str();
    bk->add_option("--duration", bko.duration,
                   "How long the swarm runs: a number with an optional unit ms, s, m or h (plain: seconds), e.g. 1h, "
                   "10m, 90s (as `pheromesh run --duration`)")
        ->check(cli::duration_validator(false))
        ->capture_default_str();
    bk->add_option("--fault-every", bko.fault_every, "One fault per period, a duration as --duration (0: no faults)")
        ->check(cli::duration_validator(false))
        ->capture_default_str();
    bk->add_option("--sample-every", bko.sample_every, "Sampling period of /proc, a duration as --duration")
        ->check(cli::duration_validator(false))
        ->capture_default_str();
    bk->add_option("--warmup", bko.warmup, "Samples before this are left out of the growth fits, a duration")
        ->check(cli::duration_validator(false))
        ->capture_default_str();
    bk->add_option("--rate", bko.rate_hz, "Tick rate of every process [Hz]")->check(CLI::PositiveNumber)->capture_default_str();
    bk->add_option("--lease-ms", bko.lease_ms, "Liveliness lease [ms] (generous: a loaded host stalls)")
        ->check(CLI::Range(50, 60000))
        ->capture_default_str();
    bk->add_option("--dds", bko.dds, "DDS vendor(s) as `pheromesh run --dds` takes them")->capture_default_str();
    bk->add_option("--domain", bko.domain, "DDS domain id of the run")->check(CLI::Range(0, 232))->capture_default_str();
    bk->add_option("--out", bko.out_dir, "Output folder: soak.md, soak.csv, soak-processes.csv, run/")->capture_default_str();
    bk->add_option("--extra", bko.extra, "More arguments for `pheromesh run`, in one string");
    bk->footer(cli::kBenchSoakFooter);
  }

  void add_attach(CLI::App& app) {
    ao.dds = bus::default_vendor();
    if (const char* p = std::getenv("PHEROMESH_DDS_PROFILE"); p != nullptr && *p != '\0') ao.dds_profile = p;
    if (const char* p = std::getenv("PHEROMESH_DDS_PEERS"); p != nullptr) ao.dds_peers = p;
    at = app.add_subcommand("attach",
                                  "Monitor a running swarm from this host, found by its domain id alone: "
                                  "progress lines, metrics, and with --http the web console");
    at->add_option("--domain", ao.domain, "DDS domain id of the swarm")->check(CLI::Range(0, 232))->capture_default_str();
    at->add_option("--dds", ao.dds, "DDS vendor of the monitor: cyclone or fastdds (either reaches any swarm)")
        ->capture_default_str();
    at->add_option(
          "--dds-profile", ao.dds_profile,
          "DDS profile that reaches the swarm: cells (the default, as `pheromesh run`'s; with --dds-peers for a "
          "swarm over several hosts), onehost (same host), lan, lan-unicast (with --dds-peers), or files "
          "[env PHEROMESH_DDS_PROFILE]")
        ->capture_default_str();
    at->add_option("--dds-peers", ao.dds_peers,
                   "The swarm's hosts, comma-separated (cells, lan-unicast) [env PHEROMESH_DDS_PEERS]");
    at->add_option("--hosts-file", ao.hosts_file,
                   "The swarm's hosts, one per line, as `pheromesh run --hosts-file` takes them: stands for "
                   "--dds-peers, which must then be left out (as must $PHEROMESH_DDS_PEERS) (docs/deployment.md)")
        ->check(CLI::ExistingFile);
    at->add_option("--cell-hubs", ao.cell_hubs,
                   "cells: the most hubs (ground station and place agent replicas) on one host of the swarm, as "
                   "`pheromesh run` prints it; without it the monitor names all 120 indices a hub can have");
    at->add_option("--participant-id", ao.participant_id,
                   "cells over Fast DDS: the monitor's participant id (its ports), above 119 and past every UAV's "
                   "(120 + UAV id); default: the domain's highest below the ephemeral ports");
    at->add_option("--out", ao.out_dir, "Output folder (metrics.json, console recording)")->capture_default_str();
    at->add_option("--http", ao.http_port, "Serve the web console on this port (0: any free port)");
    at->add_option("--http-bind", ao.http_bind, "Address the console listens on (0.0.0.0: every interface)")
        ->capture_default_str();
    at->add_option("--record", ao.record, "Record the console to this file (for pheromesh replay)");
    add_mavlink_options(at, ao.mavlink, ao.mavlink_rate_hz, "the swarm", "a monitor takes no command from it");
    at->add_option("--timeout", ao.timeout_s, "Longest wait for a running swarm [s], > 0")
        ->check(CLI::Range(0.01, 86400.0))
        ->capture_default_str();
    at->add_option("--progress", ao.progress_s, "Seconds between progress lines [s], > 0")
        ->check(CLI::Range(0.01, 86400.0))
        ->capture_default_str();
    at->add_option("--process-log-level", ao.log_level,
                   "Log level of the monitor: trace, debug, info, warn, error, critical or off")
        ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
        ->capture_default_str();
    if (const char* p = std::getenv("PHEROMESH_SECURE"); p != nullptr) ao.secure = p;
    at->add_option("--secure", ao.secure,
                   "DDS Security: the swarm's directory of `pheromesh security init`; the monitor authenticates with "
                   "its read-only identity 'monitor' there (docs/security.md) [env PHEROMESH_SECURE]");
    at->footer(kAttachFooter);
  }

  void add_security(CLI::App& app) {
    auto* sec = app.add_subcommand("security", "DDS Security for a swarm: authentication, access control, encryption "
                                               "(docs/security.md)");
    sec->require_subcommand(1);
    si = sec->add_subcommand("init", "Make a swarm's CA, one identity per process (UAVs, place agents, ground "
                                           "station, read-only monitor), the governance and the signed permissions "
                                           "in DIR, for `pheromesh run --secure DIR`");
    si->add_option("DIR", sio.dir, "Directory to make (mode 0700)")->required();
    si->add_option("--scenario", sio.scenario, "The swarm's scenario: its UAVs, regions and standby setting")
        ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
    si->add_option("--uavs", sio.uavs, "UAV identities to make, >= 1 (default: the scenario's swarm.uavs)")
        ->check(CLI::Range(1U, 100000U));
    si->add_option("--regions", sio.regions, "Place-agent identities to make, >= 1 (default: the scenario's regions)")
        ->check(CLI::Range(1U, 100000U));
    si->add_flag("--standby", sio.standby, "Also an identity for each place agent's standby (place-R.r1)");
    si->add_option("--probes", sio.probes, "Also identities probe-0 .. probe-N-1 for pheromesh-test-probe and benches");
    si->add_option("--protection", sio.protection,
                   "What the governance does to the traffic: encrypt (AES-GCM), sign (GMAC, readable) or none "
                   "(authentication and access control only)")
        ->check(CLI::IsMember({"encrypt", "sign", "none"}))
        ->capture_default_str();
    si->add_option("--days", sio.days, "Validity of the certificates and permissions [days], >= 1")
        ->check(CLI::Range(1U, 100000U))
        ->capture_default_str();
    si->add_flag("--force", sio.force, "Replace the files of an earlier `security init` in DIR");
    si->footer(cli::kSecurityFooter);
  }
};

}  // namespace

std::unique_ptr<ProcessCommands> add_process_commands(CLI::App& app) { return std::make_unique<FullCommands>(app); }

bool processes_built() { return true; }

}  // namespace pheromesh::cli
