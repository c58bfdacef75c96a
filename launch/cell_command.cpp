#include "cell_command.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>
#include <set>
#include <thread>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/cliutil/scenario_paths.hpp"
#include "pheromesh/core/scenario.hpp"

namespace pheromesh::cli {
namespace {

// A member alone at its address: any participant id is free there. Fast DDS
// needs one (runtime::bus_options), Cyclone takes its ports from the kernel.
constexpr uint32_t kLoneMemberId = 1;

constexpr const char* kCellFooter = R"(Each process of a swarm in containers or pods runs alone at an address of its
own and finds the hubs it talks to (the ground station, the place agents) by
name: every hub takes participant index 0 at its own address, so the swarm has
no participant-index ceiling (docs/deploy-containers.md, "Cells"). A UAV names
its home place agent (and its backup, as reserve), a place agent the ground
station and the other place agents, the ground station the place agents, a
monitor all of them. Names that do not resolve yet (pods that start together)
are waited for, up to --wait.

The output is the environment the process reads, NAME=VALUE per line:
  PHEROMESH_CELL             the cell, peers by address (docs/dds.md, "Cell discovery")
  PHEROMESH_PARTICIPANT_ID   a member's (UAV's, monitor's) Fast DDS participant id

Examples:
  pheromesh cell uav 3 --scenario small-test                      # compose: place-0 .. place-3, ground
  pheromesh cell place 2 --scenario small-test \
      --place-name 'place-{region}.pheromesh-swarm' --ground-name ground.pheromesh-swarm   # Kubernetes
  env $(pheromesh cell uav 3 --scenario small-test) pheromesh-uav --scenario small-test --id 3 --dds-profile cells
)";

core::Result<std::optional<std::vector<std::string>>> resolve_by_dns(const std::string& name) {
  auto r = bus::resolve_peers(name);
  if (!r) return r.error();
  if (r->addresses.empty()) return std::optional<std::vector<std::string>>{};
  return std::optional<std::vector<std::string>>{r->addresses};
}

}  // namespace

core::Result<std::variant<bus::CellDiscovery, Unresolved>> resolve_named_cell(
    const bus::CellDiscovery& named, const NameResolver& resolve,
    const std::function<std::optional<std::string>(const std::string&)>& route) {
  bus::CellDiscovery cell = named;
  Unresolved missing;
  std::map<std::string, std::string> address_of;  // name -> address
  std::map<std::string, std::string> name_at;     // address -> first name there
  for (auto* list : {&cell.peers, &cell.reserve}) {
    for (auto& peer : *list) {
      if (auto known = address_of.find(peer.address); known != address_of.end()) {
        peer.address = known->second;
        continue;
      }
      auto got = resolve(peer.address);
      if (!got) return got.error();
      if (!got.value()) {
        missing.names.push_back(peer.address);
        continue;
      }
      const auto& addresses = *got.value();
      if (addresses.size() != 1) {
        return core::Error{"'" + peer.address + "' resolves to " + std::to_string(addresses.size()) +
                           " addresses: in cells each name is one process's (one pod, one container)"};
      }
      if (auto other = name_at.find(addresses.front()); other != name_at.end()) {
        return core::Error{"'" + other->second + "' and '" + peer.address + "' resolve to the same address " +
                           addresses.front() +
                           ": hubs found by name take participant index 0 at their address, so each needs an "
                           "address of its own (on one host, `pheromesh run` gives hubs indices instead)"};
      }
      name_at.emplace(addresses.front(), peer.address);
      address_of.emplace(peer.address, addresses.front());
      peer.address = addresses.front();
    }
  }
  if (!missing.names.empty()) return std::variant<bus::CellDiscovery, Unresolved>{missing};
  if (!cell.peers.empty()) {
    auto local = route(cell.peers.front().address);
    if (!local) return core::Error{"this process has no route to " + cell.peers.front().address};
    cell.interface_address = *local;
  } else if (cell.interface_address.empty()) {
    return core::Error{"a cell without peers: nothing to name (a swarm of one region has a ground station)"};
  }
  return std::variant<bus::CellDiscovery, Unresolved>{cell};
}

std::vector<std::string> cell_environment(const std::string& role, const bus::CellDiscovery& cell) {
  std::vector<std::string> out{std::string(bus::kCellEnv) + "=" + bus::format_cell(cell)};
  if (role == "uav" || role == "monitor") out.push_back("PHEROMESH_PARTICIPANT_ID=" + std::to_string(kLoneMemberId));
  return out;
}

CLI::App* add_cell_command(CLI::App& app, CellCommandOptions& o) {
  auto* c = app.add_subcommand("cell",
                               "Print the cell (discovery peers) of one process that runs alone at its own address, "
                               "its hubs found by name: containers, pods (docs/deploy-containers.md)");
  c->add_option("ROLE", o.role, "place, uav, ground or monitor")
      ->required()
      ->check(CLI::IsMember({"place", "uav", "ground", "monitor"}));
  c->add_option("INDEX", o.index, "place: its region; uav: its id (none for ground and monitor)");
  c->add_option("--scenario", o.scenario, "The swarm's scenario, a file or a shipped name: its regions")
      ->required()
      ->envname("PHEROMESH_SCENARIO")
      ->transform(CLI::Validator(cli::resolve_scenario_argument, "FILE|NAME"));
  c->add_option("--domain", o.domain, "DDS domain id of the swarm")
      ->check(CLI::Range(0, 232))
      ->envname("PHEROMESH_DOMAIN")
      ->capture_default_str();
  c->add_option("--clock", o.clock, "realtime or lockstep (a lockstep UAV names its backup from the start)")
      ->check(CLI::IsMember({"realtime", "lockstep"}))
      ->envname("PHEROMESH_CLOCK")
      ->capture_default_str();
  c->add_option("--place-name", o.names.place,
                "Name of region {region}'s place agent: compose's service names, or a StatefulSet's pods under its "
                "headless Service, e.g. 'place-{region}.pheromesh-swarm'")
      ->envname("PHEROMESH_PLACE_NAME")
      ->capture_default_str();
  c->add_option("--ground-name", o.names.ground, "Name of the ground station")
      ->envname("PHEROMESH_GROUND_NAME")
      ->capture_default_str();
  c->add_option("--wait", o.wait_s, "Longest wait for the names to resolve [s], >= 0")
      ->check(CLI::Range(0.0, 86400.0))
      ->envname("PHEROMESH_WAIT_PEERS_S")
      ->capture_default_str();
  c->footer(kCellFooter);
  return c;
}

int run_cell_command(const CellCommandOptions& o) {
  if (auto err = check_hub_names(o.names)) {
    spdlog::error("pheromesh cell: {}", *err);
    return 2;
  }
  const bool indexed = o.role == "place" || o.role == "uav";
  if (indexed != o.index.has_value()) {
    spdlog::error("pheromesh cell {}: {}", o.role,
                  indexed ? "give its index (place: the region, uav: the UAV id)" : "takes no index");
    return 2;
  }
  auto scenario = core::load_scenario(o.scenario, {});
  if (!scenario) {
    spdlog::error("invalid scenario:\n{}", scenario.error().message);
    return 2;
  }
  if (scenario->standby) {
    spdlog::error(
        "pheromesh cell: the scenario runs standbys (run.standby), which cells found by name do not "
        "have yet: use --dds-profile lan or lan-unicast for this swarm (docs/deploy-containers.md)");
    return 2;
  }
  SwarmShape shape;
  shape.regions = static_cast<uint32_t>(scenario->geometry().region_count());
  shape.uavs = static_cast<uint32_t>(scenario->uavs);
  shape.domain = o.domain;
  shape.lockstep = o.clock == "lockstep";
  if (o.role == "place" && *o.index >= shape.regions) {
    spdlog::error("pheromesh cell place {}: the scenario has regions 0..{}", *o.index, shape.regions - 1);
    return 2;
  }
  const auto named = named_cell(shape, o.names, o.role, o.index.value_or(0));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(o.wait_s);
  for (bool said = false;; said = true) {
    auto resolved = resolve_named_cell(named, resolve_by_dns, local_address_towards);
    if (!resolved) {
      spdlog::error("pheromesh cell {}: {}", o.role, resolved.error().message);
      return 2;
    }
    if (auto* cell = std::get_if<bus::CellDiscovery>(&resolved.value())) {
      auto checked = bus::check_cell(*cell);
      if (!checked) {
        spdlog::error("pheromesh cell {}: {}", o.role, checked.error().message);
        return 2;
      }
      for (const auto& line : cell_environment(o.role, checked.value())) std::cout << line << '\n';
      return 0;
    }
    const auto& missing = std::get<Unresolved>(resolved.value()).names;
    std::string list;
    for (const auto& n : missing) list += (list.empty() ? "" : ", ") + n;
    if (std::chrono::steady_clock::now() >= deadline) {
      spdlog::error("pheromesh cell {}: {} did not resolve within {} s (--wait)", o.role, list, o.wait_s);
      return 3;
    }
    if (!said) spdlog::info("pheromesh cell {}: waiting for {} to resolve", o.role, list);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
}

}  // namespace pheromesh::cli
