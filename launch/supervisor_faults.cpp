// The fault side of `pheromesh run` (docs/faults.md): each action of the
// plan's schedule on real processes: kill (SIGKILL), stop (SIGSTOP ...
// SIGCONT), restart (SIGKILL ... started again), standby (one more place
// agent), partition and loss (nft rules on the namespaces' bridge, made by
// prepare_netns). Realtime runs time them by the launcher's clock, lockstep
// runs by the conductor's `faults K` line (Supervisor::answer_faults). The
// schedule itself is merged and checked by the plan (launch/run_plan.cpp).
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <nlohmann/json.hpp>

#include "supervisor.hpp"

namespace pheromesh::cli {

namespace {

using core::FaultAction;

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string out;
  for (const auto& s : v) out += (out.empty() ? "" : sep) + s;
  return out;
}

double round3(double v) { return std::round(v * 1000.0) / 1000.0; }

}  // namespace

std::optional<std::string> Supervisor::prepare_netns() {
  if (!faults_ || !faults_->schedule().has_network()) return std::nullopt;
  auto subnet = parse_subnet(plan_.options.netns_subnet);
  if (!subnet) return subnet.error().message;
  if (geteuid() == 0) {
    const auto stale = remove_stale_namespaces();
    if (!stale.empty()) {
      spdlog::warn("removed {} network namespaces left by launchers that are gone: {}", stale.size(), join(stale, " "));
    }
  }
  std::vector<std::string> names{"ground"};
  for (uint32_t r = 0; r < plan_.regions; ++r) names.push_back(process_name("place", r));
  for (uint32_t u = 0; u < plan_.uavs; ++u) names.push_back(process_name("uav", u));
  auto ns = std::make_unique<NetnsSwarm>("phm-" + std::to_string(getpid()), subnet.value());
  const auto t0 = std::chrono::steady_clock::now();
  if (auto err = ns->create(names)) return err;
  netns_setup_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  spdlog::info(
      "network faults: {} processes in network namespaces {}-0..{} on a bridge in {}-sw, addresses from {} "
      "(ground {}), DDS profile {}; made in {:.2f} s",
      names.size(), ns->prefix(), names.size() - 1, ns->prefix(), subnet->text(), ns->address_of("ground"),
      plan_.options.dds_profile, *netns_setup_s_);
  netns_ = std::move(ns);
  return std::nullopt;
}

double Supervisor::fault_clock_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
}

ChildProcess* Supervisor::resolve(const core::FaultTarget& t) {
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

void Supervisor::fault_not_running(const core::FaultEvent& e, const core::FaultTarget& t, const std::string& when,
                                   FaultActs& acts) {
  spdlog::warn("fault '{}': {} is not running {}; nothing to do for it", e.text, t.process_name(), when);
  acts.notes.push_back(t.process_name() + " was not running");
}

void Supervisor::fault_failed(const core::FaultEvent& e, const std::string& err, FaultActs& acts) {
  spdlog::error("fault '{}' could not be injected: {}", e.text, err);
  acts.notes.push_back("failed: " + err);
  ++fault_failures_;
}

void Supervisor::execute_fault(std::size_t i, std::optional<uint32_t> tick) {
  const core::FaultEvent e = faults_->event(i);  // a copy: spawning below may grow children_, not the schedule
  const double now = fault_clock_s();
  const std::string when = tick ? fmt::format("before tick {}", *tick) : fmt::format("at {:.2f} s", now);
  FaultActs acts;
  switch (e.action) {
    case FaultAction::Kill:
    case FaultAction::Restart:
      inject_kill(e, when, acts);
      break;
    case FaultAction::Stop:
      inject_stop(e, when, acts);
      break;
    case FaultAction::Standby:
      inject_standby(e, when, acts);
      break;
    case FaultAction::Partition:
    case FaultAction::Loss:
      inject_network(i, e, when, acts);
      break;
  }
  fault_names_[i] = acts.names;
  fault_pids_[i] = acts.pids;
  faults_->begin(i, now, acts.names, tick, join(acts.notes, "; "));
}

void Supervisor::inject_kill(const core::FaultEvent& e, const std::string& when, FaultActs& acts) {
  for (const auto& t : e.targets) {
    ChildProcess* c = resolve(t);
    if (c == nullptr) {
      fault_not_running(e, t, when, acts);
      continue;
    }
    spdlog::warn(
        "fault: SIGKILL to {} (pid {}) {}{}", c->name, c->pid, when,
        e.action == FaultAction::Restart ? fmt::format(", to be started again in {:.2f} s", e.duration_s) : "");
    acts.names.push_back(c->name);
    acts.pids.push_back(c->pid);
    // Reaped before going on: a lockstep kill is complete when the
    // conductor hears of it, and a restart needs the old one gone.
    kill_and_reap(*c);
  }
}

void Supervisor::inject_stop(const core::FaultEvent& e, const std::string& when, FaultActs& acts) {
  for (const auto& t : e.targets) {
    ChildProcess* c = resolve(t);
    if (c == nullptr) {
      fault_not_running(e, t, when, acts);
      continue;
    }
    spdlog::warn("fault: SIGSTOP to {} (pid {}) {} for {:.2f} s", c->name, c->pid, when, e.duration_s);
    kill(c->pid, SIGSTOP);
    c->stopped = true;
    acts.names.push_back(c->name);
    acts.pids.push_back(c->pid);
  }
}

void Supervisor::inject_standby(const core::FaultEvent& e, const std::string& when, FaultActs& acts) {
  for (const auto& t : e.targets) {
    const uint32_t replica = top_replica_[t.index] + 1;
    try {
      spawn_place(t.index, replica);
    } catch (const std::exception& ex) {
      fault_failed(e, ex.what(), acts);
      continue;
    }
    const ChildProcess* c = find(process_name("place", t.index, replica));
    spdlog::warn("fault: started standby {} (pid {}) {}", c->name, c->pid, when);
    acts.names.push_back(c->name);
    acts.pids.push_back(c->pid);
  }
}

void Supervisor::inject_network(std::size_t i, const core::FaultEvent& e, const std::string& when, FaultActs& acts) {
  for (const auto& t : e.targets) {
    // A process that is not running keeps its namespace: whoever runs
    // there next (a restart) is cut off or lossy too.
    const ChildProcess* c = resolve(t);
    acts.names.push_back(c != nullptr ? c->name : t.process_name());
    if (c != nullptr) acts.pids.push_back(c->pid);
  }
  const auto err = e.action == FaultAction::Partition ? netns_->cut_off(static_cast<int>(i), acts.names)
                                                      : netns_->drop_share(static_cast<int>(i), e.loss, acts.names);
  std::vector<std::string> pid_list;
  for (const pid_t p : acts.pids) pid_list.push_back(std::to_string(p));
  const std::string who =
      acts.names.empty() ? std::string("every process") : join(acts.names, ",") + " (pid " + join(pid_list, ",") + ")";
  if (err) {
    fault_failed(e, *err, acts);
  } else if (e.action == FaultAction::Partition) {
    spdlog::warn("fault: {} cut off from every other process {} for {:.2f} s", who, when, e.duration_s);
  } else {
    spdlog::warn("fault: {:.0f} % of the packets to {} dropped {} for {:.2f} s", 100.0 * e.loss, who, when,
                 e.duration_s);
  }
}

void Supervisor::end_fault(std::size_t i, FaultEnd end) {
  const double now = fault_clock_s();
  std::vector<std::string> notes;
  switch (faults_->event(i).action) {
    case FaultAction::Stop:
      continue_stopped(i, now, end);
      if (end == FaultEnd::RunOver) notes.emplace_back("cut short: the run ended");
      break;
    case FaultAction::Partition:
    case FaultAction::Loss:
      lift_network(i, now, end, notes);
      if (end == FaultEnd::RunOver) notes.emplace_back("cut short: the run ended");
      break;
    case FaultAction::Restart:
      restart_killed(i, now, end, notes);
      break;
    case FaultAction::Kill:
    case FaultAction::Standby:
      break;
  }
  faults_->end(i, now, join(notes, "; "));
}

void Supervisor::continue_stopped(std::size_t i, double now, FaultEnd end) {
  for (const auto& name : fault_names_[i]) {
    ChildProcess* c = find(name);
    if (c == nullptr || !c->running || !c->stopped) continue;
    kill(c->pid, SIGCONT);
    c->stopped = false;
    spdlog::warn("fault: SIGCONT to {} (pid {}) at {:.2f} s{}", c->name, c->pid, now,
                 end == FaultEnd::RunOver ? " (the run is ending)" : "");
  }
}

void Supervisor::lift_network(std::size_t i, double now, FaultEnd end, std::vector<std::string>& notes) {
  const core::FaultEvent& e = faults_->event(i);
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
    spdlog::warn("fault: '{}' lifted at {:.2f} s{}{}", e.text, now, what,
                 end == FaultEnd::RunOver ? " (the run is ending)" : "");
  }
  if (counts.dropped) fault_packets_[i] = {counts.seen.value_or(0), *counts.dropped};
}

void Supervisor::restart_killed(std::size_t i, double now, FaultEnd end, std::vector<std::string>& notes) {
  const std::string text = faults_->event(i).text;
  for (const auto& name : fault_names_[i]) {
    if (end == FaultEnd::RunOver) {
      notes.push_back(name + " not started again: the run ended");
      continue;
    }
    auto pid = respawn(name);
    if (!pid) {
      spdlog::warn("fault '{}': {} not started again: {}", text, name, pid.error().message);
      notes.push_back(name + " not started again: " + pid.error().message);
      continue;
    }
    spdlog::warn("fault: {} started again (pid {}) at {:.2f} s", name, pid.value(), now);
    fault_pids_[i].push_back(pid.value());
  }
}

void Supervisor::end_due_faults() {
  if (!faults_) return;
  for (const auto i : faults_->take_ends_at(fault_clock_s())) end_fault(i, FaultEnd::Due);
}

void Supervisor::end_open_faults() {
  if (!faults_) return;
  for (const auto i : faults_->take_all_ends()) end_fault(i, FaultEnd::RunOver);
}

std::string Supervisor::answer_faults(uint32_t tick) {
  last_fault_tick_ = tick;
  if (faults_) {
    for (const auto i : faults_->take_due_before_tick(tick)) execute_fault(i, tick);
  }
  reap();
  const std::string gone = join(gone_since_answer_, ",");
  gone_since_answer_.clear();
  return "ok gone " + (gone.empty() ? std::string("-") : gone);
}

nlohmann::json Supervisor::fault_metrics() const {
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
  nlohmann::json m = {{"faults", std::move(list)}, {"faults_failed", fault_failures_}};
  if (netns_setup_s_) {
    m["netns"] = {{"prefix", netns_ ? netns_->prefix() : std::string()},
                  {"subnet", plan_.options.netns_subnet},
                  {"namespaces", netns_ ? netns_->size() + 1 : 0},  // + the switch
                  {"setup_s", round3(*netns_setup_s_)},
                  {"profile", plan_.options.dds_profile}};
  }
  return m;
}

}  // namespace pheromesh::cli
