// The ground station's flags (pheromesh-ground --help), by group.
#include <CLI/CLI.hpp>
#include <string>

#include "ground_app.hpp"
#include "pheromesh/console/mavlink_feed.hpp"

namespace pheromesh::groundstation {

namespace {

void add_run_options(CLI::App& app, GroundConfig& cfg) {
  runtime::add_common_options(app, cfg.common);
  app.add_option("--out", cfg.out_dir,
                 "Output folder (metrics.json, series.csv, final_field.txt/.csv), relative to the current directory")
      ->capture_default_str();
  app.add_option("--progress", cfg.progress_period_s, "Seconds between progress lines [s], > 0")
      ->check(CLI::Range(0.01, 86400.0))
      ->capture_default_str();
  app.add_option("--phase-timeout", cfg.phase_timeout_s, "Lockstep: longest wait for one phase [s]")
      ->capture_default_str();
  app.add_option("--start-timeout", cfg.start_timeout_s,
                 "Lockstep: longest wait before tick 0 for every UAV and place agent to report that it matched the "
                 "readers it deposits to; past it the run is refused and the ground station exits 1 [s] (default: "
                 "60 s + 1 s per process)")
      ->check(CLI::Range(0.001, 86400.0));
  app.add_option("--departed-grace", cfg.departed_grace_s,
                 "A UAV whose liveliness lapsed and that sent nothing for this long is no longer waited for: by the "
                 "lockstep conductor, and by --until-done, which ends the run only once it finished or this passed "
                 "(one killed by the launcher or the console is dropped at once) [s]")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 86400.0));
}

void add_console_options(CLI::App& app, GroundConfig& cfg) {
  app.add_option("--http", cfg.http_port, "Serve the web console and /metrics on this port (0: any free port)");
  app.add_option("--http-bind", cfg.http_bind, "Address the console listens on (0.0.0.0: every interface)")
      ->capture_default_str();
  app.add_option(
         "--http-threads", cfg.http_limits.threads,
         "Console requests served at once; slow and idle connections wait without a thread (docs/console.md, Limits)")
      ->capture_default_str()
      ->check(CLI::Range(1U, 64U));
  app.add_option("--http-max-body", cfg.http_limits.max_body,
                 "Largest request body the console reads [byte]; larger ones get 413 unread")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{256}, std::size_t{16} << 20));
  app.add_option("--console-hz", cfg.console_hz, "Console frames per second")
      ->capture_default_str()
      ->check(CLI::Range(0.2, 50.0));
  app.add_option("--record", cfg.record_path, "Record the console frames to this file (read by `pheromesh replay`)");
  app.add_flag("--tracks", cfg.tracks, "Also write OUT/tracks.csv: every UAV state heard (tick, uav, x, y, role)");
}

void add_swarm_options(CLI::App& app, GroundConfig& cfg) {
  app.add_flag("--until-done", cfg.until_done,
               "End the run when every expected UAV finished or was lost: publish a signed End, on which every place "
               "agent finishes, then write metrics.json and exit (a swarm without pheromesh run's single launcher: "
               "several hosts, containers; needs $PHEROMESH_CONTROL_KEY, the same in every process)");
  app.add_option("--launcher-fd", cfg.launcher_fd, "Control socket inherited from `pheromesh run` (kill / restart)");
  app.add_option(
         "--fault-ticks", cfg.fault_ticks,
         "Lockstep: ticks with faults, comma-separated; before each one's UAV phase the conductor asks the launcher "
         "(\"faults K\" on --launcher-fd) which processes it killed and drops them")
      ->delimiter(',');
  app.add_option("--faults-timeout", cfg.faults_timeout_s,
                 "Lockstep: longest wait for the launcher's answer to \"faults K\" [s]")
      ->capture_default_str();
}

void add_mavlink_options(CLI::App& app, GroundConfig& cfg) {
  app.add_option("--mavlink", cfg.mavlink,
                 "Stream the swarm to a MAVLink ground-control station (QGroundControl, Mission Planner) at "
                 "udp:HOST:PORT, e.g. udp:127.0.0.1:14550: UAVs 0..249 as vehicles (systems 1..250), every UAV as "
                 "ADS-B traffic, this ground station as system 251; it takes pause, continue and stop signed with the "
                 "swarm's MAVLink key, which it writes to OUT/mavlink.key (docs/mavlink.md)")
      ->check([](const std::string& v) {
        const auto t = console::parse_mavlink_target(v, "");
        return t ? std::string() : t.error().message;
      });
  app.add_option("--mavlink-rate-hz", cfg.mavlink_rate_hz,
                 "With --mavlink: position, attitude and ADS-B reports per UAV per second [Hz], 0.2..20 (heartbeats "
                 "go at 1 Hz)")
      ->capture_default_str()
      ->check([](const std::string& v) {
        double hz = 0;
        try {
          hz = std::stod(v);
        } catch (const std::exception&) {
          return v + ": not a number";
        }
        const auto r = console::check_mavlink_rate(hz, "");
        return r ? std::string() : r.error().message;
      });
}

}  // namespace

void add_ground_options(CLI::App& app, GroundConfig& cfg, double& attach_timeout_s) {
  add_run_options(app, cfg);
  add_console_options(app, cfg);
  add_swarm_options(app, cfg);
  add_mavlink_options(app, cfg);
  app.add_flag("--attach", cfg.attach,
               "Monitor a running swarm found by its domain id alone: take the scenario and the run's options from its "
               "place agents (no --scenario needed), show and record what happens from now on, steer nothing; exits "
               "when every place agent finished (or on SIGINT) and writes OUT/metrics.json as seen from here");
  app.add_option("--attach-timeout", attach_timeout_s, "With --attach: longest wait for a running swarm [s]")
      ->capture_default_str();
}

}  // namespace pheromesh::groundstation
