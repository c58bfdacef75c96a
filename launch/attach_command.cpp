#include "attach_command.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "cell_layout.hpp"
#include "hosts_file.hpp"
#include "launcher.hpp"
#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/cell_discovery.hpp"

namespace pheromesh::cli {

uint32_t default_monitor_participant_id(uint32_t domain) {
  const uint32_t first = bus::unicast_discovery_port(domain, 0);
  if (first + 1 >= bus::kEphemeralPortsFrom) return 0;
  return (bus::kEphemeralPortsFrom - 2 - first) / bus::kParticipantGain;
}

std::optional<std::string> check_attach(const AttachOptions& o) {
  const bool cells = o.dds_profile == "cells";
  if (!cells && (o.cell_hubs || o.participant_id)) {
    return "--cell-hubs and --participant-id are for --dds-profile cells (the default)";
  }
  if (cells && o.cell_hubs && *o.cell_hubs == 0) return "--cell-hubs 0: a swarm has at least its ground station";
  if (cells && o.cell_hubs && *o.cell_hubs - 1 > bus::kMaxParticipantIndex) {
    return "--cell-hubs " + std::to_string(*o.cell_hubs) + ": hub indices stop at " +
           std::to_string(bus::kMaxParticipantIndex);
  }
  if (o.participant_id && *o.participant_id <= static_cast<int32_t>(bus::kMaxParticipantIndex)) {
    return "--participant-id " + std::to_string(*o.participant_id) + " is a hub's index (hubs are 0 .. " +
           std::to_string(bus::kMaxParticipantIndex) + "): give one above " +
           std::to_string(bus::kMaxParticipantIndex) + " and past every UAV's (" + std::to_string(kFirstMemberId) +
           " + UAV id)";
  }
  return std::nullopt;
}

namespace {

// The monitor's cell: a member of every hub's cell, bound to this host's
// address towards the swarm.
core::Result<bus::CellDiscovery> attach_cell(const AttachOptions& o) {
  std::vector<std::string> hosts;
  if (!o.dds_peers.empty()) {
    auto peers = bus::resolve_peers(o.dds_peers);
    if (!peers) return peers.error();
    if (!peers->unresolved.empty()) {
      return core::Error{"--dds-peers: " + peers->unresolved.front() + " does not resolve"};
    }
    hosts = std::move(peers->addresses);
  }
  std::string iface = "127.0.0.1";
  if (!hosts.empty()) {
    auto local = local_address_towards(hosts.front());
    if (!local) return core::Error{"--dds-peers: this host has no route to " + hosts.front()};
    iface = *local;
  }
  // Scan only the indices whose ports this domain has.
  uint32_t hubs = o.cell_hubs.value_or(bus::kMaxParticipantIndex + 1);
  while (hubs > 1 && bus::unicast_discovery_port(o.domain, hubs - 1) + 1 >= bus::kEphemeralPortsFrom) --hubs;
  auto cell = bus::check_cell(monitor_cell(o.domain, hubs, hosts, iface));
  if (!cell) return core::Error{"--dds-profile cells: " + cell.error().message};
  return cell;
}

}  // namespace

int run_attach(AttachOptions o) {
  if (!o.hosts_file.empty()) {
    auto file = read_hosts_file(o.hosts_file);
    HostsFlags flags;
    flags.dds_peers = o.dds_peers;
    flags.dds_peers_from = o.dds_peers_from;
    auto peers = file ? attach_peers(file.value(), flags) : core::Result<std::string>(file.error());
    if (!peers) {
      spdlog::error("{}", peers.error().message);
      return 2;
    }
    o.dds_peers = peers.value();
  }
  if (auto err = check_attach(o)) {
    spdlog::error("{}", *err);
    return 2;
  }
  if (o.dds_profile == "cells") {
    // The monitor is a member of every hub's cell (runtime::bus_options reads these).
    auto cell = attach_cell(o);
    if (!cell) {
      spdlog::error("{}", cell.error().message);
      return 2;
    }
    setenv(bus::kCellEnv, bus::format_cell(cell.value()).c_str(), 1);
    const uint32_t id =
        o.participant_id ? static_cast<uint32_t>(*o.participant_id) : default_monitor_participant_id(o.domain);
    setenv("PHEROMESH_PARTICIPANT_ID", std::to_string(id).c_str(), 1);
    // The processes take the peers from the cell: --dds-peers is not theirs.
    o.dds_peers.clear();
  }
  if (o.dds == "mixed") {
    // $PHEROMESH_DDS=mixed describes a swarm of both vendors; one process
    // takes one, and either reaches every process of such a swarm.
    o.dds = "fastdds";
    spdlog::info("the monitor is one process: it runs on Fast DDS (either vendor reaches a mixed swarm)");
  }
  const std::string exe = executable_dir() + "/pheromesh-ground";
  // clang-format off: flag, value
  std::vector<std::string> args{exe,
                                "--attach",
                                "--domain",
                                std::to_string(o.domain),
                                "--dds",
                                o.dds,
                                "--dds-profile",
                                o.dds_profile,
                                "--out",
                                o.out_dir,
                                "--attach-timeout",
                                std::to_string(o.timeout_s),
                                "--progress",
                                std::to_string(o.progress_s),
                                "--log-level",
                                o.log_level};
  // clang-format on
  if (!o.dds_peers.empty()) args.insert(args.end(), {"--dds-peers", o.dds_peers});
  if (o.http_port) args.insert(args.end(), {"--http", std::to_string(*o.http_port), "--http-bind", o.http_bind});
  if (!o.record.empty()) args.insert(args.end(), {"--record", o.record});
  if (!o.mavlink.empty()) {
    args.insert(args.end(), {"--mavlink", o.mavlink, "--mavlink-rate-hz", std::to_string(o.mavlink_rate_hz)});
  }
  if (!o.secure.empty()) args.insert(args.end(), {"--secure", o.secure});
  std::error_code ec;
  std::filesystem::create_directories(o.out_dir, ec);
  if (ec) {
    spdlog::error("cannot make {}: {}", o.out_dir, ec.message());
    return 2;
  }
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  execv(exe.c_str(), argv.data());
  spdlog::error("cannot execute {}: {}", exe, std::strerror(errno));
  return 3;
}

}  // namespace pheromesh::cli
