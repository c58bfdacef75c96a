// The fault side of `pheromesh run` (docs/faults.md): the schedule from
// --faults, --kill and the scenario, its checks, the network namespaces, and
// each action on real processes: kill (SIGKILL), stop (SIGSTOP ... SIGCONT),
// restart (SIGKILL ... started again), standby (one more place agent),
// partition and loss (nft rules on the namespaces' bridge). Realtime runs
// time them by the launcher's clock, lockstep runs by the conductor's
// `faults K` line (Launcher::answer_faults).
#include <fmt/format.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "launcher.hpp"

namespace pheromesh::cli {

namespace {

using core::FaultAction;

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : sep) + s;
  return out;
}

// Whether `exe --help` mentions `flag`: the launcher passes flags that
// other parts of issue 14 add to the processes only when they are there.
bool takes_flag(const std::string& exe, const std::string& flag) {
  const ToolResult r = run_tool({exe, "--help"});
  return r.output.find(flag) != std::string::npos;
}

double round3(double v) { return std::round(v * 1000.0) / 1000.0; }

}  // namespace

std::optional<std::string> Launcher::prepare_faults(const core::ScenarioConfig& s, uint32_t uavs, uint32_t regions) {
  // Each source is checked on its own, so that an error names it.
  const bool lockstep = o_.clock == "lockstep";
  core::FaultSchedule schedule;
  if (auto err = core::check_fault_schedule(s.faults, uavs, regions, lockstep)) {
    return o_.scenario + ": fault: " + *err;
  }
  core::merge_fault_schedules(schedule, s.faults);
  for (const auto& [spec, where] : {std::pair{o_.kill_spec, "--kill"}, std::pair{o_.faults_spec, "--faults"}}) {
    if (spec.empty()) continue;
    auto parsed = core::parse_fault_schedule(spec, where);
    if (!parsed) return parsed.error().message;
    if (auto err = core::check_fault_schedule(parsed.value(), uavs, regions, lockstep))
      return std::string(where) + ": " + *err;
    core::merge_fault_schedules(schedule, parsed.value());
  }
  if (schedule.empty()) return std::nullopt;
  bool standby = false;
  for (const auto& e : schedule.events) {
    standby = standby || e.action == FaultAction::Standby;
    const bool ends_it = e.action == FaultAction::Kill || e.action == FaultAction::Restart;
    for (const auto& t : e.targets) {
      if (t.role == "ground" && ends_it) {
        return "fault schedule: '" + e.text +
               "': the ground station cannot be killed or restarted (it conducts the "
               "run and writes metrics.json); stop, partition and loss may target it";
      }
    }
  }
  if (schedule.has_network()) {
    if (o_.http_port) {
      return "fault schedule: partition and loss run the ground station in a network namespace of its own, where "
             "the web console (--http) cannot be reached from this host; leave out --http or the network faults";
    }
    if (o_.discovery_server) {
      return "fault schedule: partition and loss do not work with --discovery-server (the server listens on this "
             "host's loopback, outside the processes' network namespaces)";
    }
    // The one-host profiles speak on loopback only; in a namespace of its
    // own each process must speak on its veth (deploy/dds/*-netns.xml).
    if (o_.dds_profile == "onehost" || o_.dds_profile == "onehost-unicast") {
      o_.dds_profile = "netns";
    } else if (o_.dds_profile != "netns") {
      spdlog::warn(
          "network faults: every process runs in its own network namespace; DDS profile '{}' must not "
          "limit it to the loopback interface (the netns profile is made for this)",
          o_.dds_profile);
    }
  }
  // A standby started later needs a swarm whose processes all run with
  // --standby (the QoS of the place agents' output): the run becomes one.
  if (standby && !standby_) {
    spdlog::info("fault schedule: 'standby' events: every process runs with --standby");
    standby_ = true;
  }
  if (lockstep && !takes_flag(bin_dir_ + "/pheromesh-ground", "--fault-ticks")) {
    return "fault schedule: a lockstep run injects faults between ticks conducted by the ground station "
           "(--fault-ticks), which this build's pheromesh-ground does not take yet";
  }
  std::vector<std::string> items;
  for (const auto& e : schedule.events) items.push_back(e.text);
  spdlog::info("fault schedule ({} events): {}", items.size(), join(items, "; "));
  faults_.emplace(std::move(schedule));
  return std::nullopt;
}

std::optional<std::string> Launcher::prepare_netns(uint32_t uavs, uint32_t regions) {
  if (!faults_ || !faults_->schedule().has_network()) return std::nullopt;
  auto subnet = parse_subnet(o_.netns_subnet);
  if (!subnet) return subnet.error().message;
  if (geteuid() == 0) {
    const auto stale = remove_stale_namespaces();
    if (!stale.empty()) {
      spdlog::warn("removed {} network namespaces left by launchers that are gone: {}", stale.size(), join(stale, " "));
    }
  }
  std::vector<std::string> names{"ground"};
  for (uint32_t r = 0; r < regions; ++r) names.push_back(process_name("place", r));
  for (uint32_t u = 0; u < uavs; ++u) names.push_back(process_name("uav", u));
  auto ns = std::make_unique<NetnsSwarm>("phm-" + std::to_string(getpid()), subnet.value());
  const auto t0 = std::chrono::steady_clock::now();
  if (auto err = ns->create(names)) return err;
  netns_setup_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  spdlog::info(
      "network faults: {} processes in network namespaces {}-0..{} on a bridge in {}-sw, addresses from {} "
      "(ground {}), DDS profile {}; made in {:.2f} s",
      names.size(), ns->prefix(), names.size() - 1, ns->prefix(), subnet->text(), ns->address_of("ground"),
      o_.dds_profile, *netns_setup_s_);
  netns_ = std::move(ns);
  return std::nullopt;
}

double Launcher::fault_clock_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
}

ChildProcess* Launcher::resolve(const core::FaultTarget& t) {
  if (t.role != "place") {
    ChildProcess* c = find(t.process_name());
    return c != nullptr && c->running ? c : nullptr;
  }
  ChildProcess* best = nullptr;
  for (auto& c : children_) {
    if (c.role == "place" && c.index == t.index && c.running && (best == nullptr || c.replica < best->replica))
      best = &c;
  }
  return best;
}

void Launcher::execute_fault(std::size_t i, std::optional<uint32_t> tick) {
  const core::FaultEvent e = faults_->event(i);  // a copy: spawning below may grow children_, not the schedule
  const double now = fault_clock_s();
  const std::string when = tick ? fmt::format("before tick {}", *tick) : fmt::format("at {:.2f} s", now);
  std::vector<std::string> names, notes;
  std::vector<pid_t> pids;
  auto not_running = [&](const core::FaultTarget& t) {
    spdlog::warn("fault '{}': {} is not running {}; nothing to do for it", e.text, t.process_name(), when);
    notes.push_back(t.process_name() + " was not running");
  };
  auto failed = [&](const std::string& err) {
    spdlog::error("fault '{}' could not be injected: {}", e.text, err);
    notes.push_back("failed: " + err);
    ++fault_failures_;
  };
  switch (e.action) {
    case FaultAction::Kill:
    case FaultAction::Restart:
      for (const auto& t : e.targets) {
        ChildProcess* c = resolve(t);
        if (c == nullptr) {
          not_running(t);
          continue;
        }
        spdlog::warn(
            "fault: SIGKILL to {} (pid {}) {}{}", c->name, c->pid, when,
            e.action == FaultAction::Restart ? fmt::format(", to be started again in {:.2f} s", e.duration_s) : "");
        names.push_back(c->name);
        pids.push_back(c->pid);
        // Reaped before going on: a lockstep kill is complete when the
        // conductor hears of it, and a restart needs the old one gone.
        kill_and_reap(*c);
      }
      break;
    case FaultAction::Stop:
      for (const auto& t : e.targets) {
        ChildProcess* c = resolve(t);
        if (c == nullptr) {
          not_running(t);
          continue;
        }
        spdlog::warn("fault: SIGSTOP to {} (pid {}) {} for {:.2f} s", c->name, c->pid, when, e.duration_s);
        kill(c->pid, SIGSTOP);
        c->stopped = true;
        names.push_back(c->name);
        pids.push_back(c->pid);
      }
      break;
    case FaultAction::Standby:
      for (const auto& t : e.targets) {
        const uint32_t replica = top_replica_[t.index] + 1;
        try {
          spawn_place(t.index, replica);
        } catch (const std::exception& ex) {
          failed(ex.what());
          continue;
        }
        const ChildProcess* c = find(process_name("place", t.index, replica));
        spdlog::warn("fault: started standby {} (pid {}) {}", c->name, c->pid, when);
        names.push_back(c->name);
        pids.push_back(c->pid);
      }
      break;
    case FaultAction::Partition:
    case FaultAction::Loss: {
      for (const auto& t : e.targets) {
        // A process that is not running keeps its namespace: whoever runs
        // there next (a restart) is cut off or lossy too.
        const ChildProcess* c = resolve(t);
        names.push_back(c != nullptr ? c->name : t.process_name());
        if (c != nullptr) pids.push_back(c->pid);
      }
      const auto err = e.action == FaultAction::Partition ? netns_->cut_off(static_cast<int>(i), names)
                                                          : netns_->drop_share(static_cast<int>(i), e.loss, names);
      std::vector<std::string> pid_list;
      for (const pid_t p : pids) pid_list.push_back(std::to_string(p));
      const std::string who =
          names.empty() ? std::string("every process") : join(names, ",") + " (pid " + join(pid_list, ",") + ")";
      if (err) {
        failed(*err);
      } else if (e.action == FaultAction::Partition) {
        spdlog::warn("fault: {} cut off from every other process {} for {:.2f} s", who, when, e.duration_s);
      } else {
        spdlog::warn("fault: {:.0f} % of the packets to {} dropped {} for {:.2f} s", 100.0 * e.loss, who, when,
                     e.duration_s);
      }
      break;
    }
  }
  fault_names_[i] = names;
  fault_pids_[i] = pids;
  faults_->begin(i, now, names, tick, join(notes, "; "));
}

void Launcher::end_fault(std::size_t i, bool run_over) {
  const core::FaultEvent e = faults_->event(i);
  const double now = fault_clock_s();
  std::vector<std::string> notes;
  switch (e.action) {
    case FaultAction::Stop:
      for (const auto& name : fault_names_[i]) {
        ChildProcess* c = find(name);
        if (c == nullptr || !c->running || !c->stopped) continue;
        kill(c->pid, SIGCONT);
        c->stopped = false;
        spdlog::warn("fault: SIGCONT to {} (pid {}) at {:.2f} s{}", c->name, c->pid, now,
                     run_over ? " (the run is ending)" : "");
      }
      if (run_over) notes.emplace_back("cut short: the run ended");
      break;
    case FaultAction::Partition:
    case FaultAction::Loss: {
      NetnsSwarm::RuleCounts counts;
      if (auto err = netns_->remove_rules(static_cast<int>(i), &counts)) {
        spdlog::error("fault '{}': cannot remove its rules: {}", e.text, *err);
        notes.push_back("rules not removed: " + *err);
        ++fault_failures_;
      } else {
        std::string what;
        if (counts.dropped) what = fmt::format("; {} packets dropped", *counts.dropped);
        if (counts.dropped && counts.seen && *counts.seen > 0) {
          what += fmt::format(" of {} ({:.1f} %)", *counts.seen,
                              100.0 * static_cast<double>(*counts.dropped) / static_cast<double>(*counts.seen));
        }
        spdlog::warn("fault: '{}' lifted at {:.2f} s{}{}", e.text, now, what, run_over ? " (the run is ending)" : "");
      }
      if (counts.dropped) fault_packets_[i] = {counts.seen.value_or(0), *counts.dropped};
      if (run_over) notes.emplace_back("cut short: the run ended");
      break;
    }
    case FaultAction::Restart:
      for (const auto& name : fault_names_[i]) {
        if (run_over) {
          notes.push_back(name + " not started again: the run ended");
          continue;
        }
        auto pid = respawn(name);
        if (!pid) {
          spdlog::warn("fault '{}': {} not started again: {}", e.text, name, pid.error().message);
          notes.push_back(name + " not started again: " + pid.error().message);
          continue;
        }
        spdlog::warn("fault: {} started again (pid {}) at {:.2f} s", name, pid.value(), now);
        fault_pids_[i].push_back(pid.value());
      }
      break;
    case FaultAction::Kill:
    case FaultAction::Standby:
      break;
  }
  faults_->end(i, now, join(notes, "; "));
}

void Launcher::end_due_faults() {
  if (!faults_) return;
  for (const auto i : faults_->take_ends_at(fault_clock_s())) end_fault(i, false);
}

void Launcher::end_open_faults() {
  if (!faults_) return;
  for (const auto i : faults_->take_all_ends()) end_fault(i, true);
}

std::string Launcher::answer_faults(uint32_t tick) {
  last_fault_tick_ = tick;
  if (faults_) {
    for (const auto i : faults_->take_due_before_tick(tick)) execute_fault(i, tick);
  }
  reap();
  const std::string gone = join(gone_since_answer_, ",");
  gone_since_answer_.clear();
  return "ok gone " + (gone.empty() ? std::string("-") : gone);
}

void Launcher::add_fault_metrics(nlohmann::json& m) const {
  nlohmann::json list = nlohmann::json::array();
  if (faults_) {
    for (const auto& r : faults_->records()) {
      const core::FaultEvent& e = faults_->event(r.event);
      nlohmann::json f = {{"action", core::to_string(r.action)},
                          {"event", e.text},
                          {"targets", r.targets},
                          {"at_s", round3(r.at_s)},
                          {"duration_s", round3(r.duration_s)},
                          {"done_at_s", r.done_at_s ? nlohmann::json(round3(*r.done_at_s)) : nlohmann::json(nullptr)}};
      if (r.tick) f["tick"] = *r.tick;
      if (e.action == FaultAction::Loss) f["loss"] = e.loss;
      const auto pids = fault_pids_.find(r.event);
      f["pids"] = pids != fault_pids_.end() ? pids->second : std::vector<pid_t>{};
      if (const auto p = fault_packets_.find(r.event); p != fault_packets_.end()) {
        f["dropped_packets"] = p->second.second;
        if (e.action == FaultAction::Loss) f["seen_packets"] = p->second.first;
      }
      if (!r.note.empty()) f["note"] = r.note;
      list.push_back(std::move(f));
    }
  }
  m["faults"] = std::move(list);
  m["faults_failed"] = fault_failures_;
  if (netns_setup_s_) {
    m["netns"] = {{"prefix", netns_ ? netns_->prefix() : std::string()},
                  {"subnet", o_.netns_subnet},
                  {"namespaces", netns_ ? netns_->size() + 1 : 0},  // + the switch
                  {"setup_s", round3(*netns_setup_s_)},
                  {"profile", o_.dds_profile}};
  }
}

}  // namespace pheromesh::cli
