#include "attach_command.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "launcher.hpp"
#include "pheromesh/bus/cell_discovery.hpp"

namespace pheromesh::cli {

std::optional<std::string> check_attach(const AttachOptions& o) {
  const bool cells = o.dds_profile == "cells";
  if (cells && !o.cell_hubs) {
    return "--dds-profile cells needs --cell-hubs: the number of the swarm's hubs (the ground station and every "
           "place agent replica), which `pheromesh run` prints in its \"watch it from this host\" line";
  }
  if (!cells && (o.cell_hubs || o.participant_id)) {
    return "--cell-hubs and --participant-id are for --dds-profile cells";
  }
  if (cells && *o.cell_hubs == 0) return "--cell-hubs 0: a swarm has at least its ground station";
  if (cells && *o.cell_hubs - 1 > bus::kMaxParticipantIndex) {
    return "--cell-hubs " + std::to_string(*o.cell_hubs) + ": hub indices stop at " +
           std::to_string(bus::kMaxParticipantIndex);
  }
  if (cells && o.dds != "cyclone" && !o.participant_id) {
    // Without one Fast DDS takes the first free index and can bind a hub's port.
    return "a Fast DDS monitor in cells needs --participant-id, past every hub's and UAV's (`pheromesh run` prints "
           "one), or --dds cyclone";
  }
  if (o.participant_id && *o.participant_id < static_cast<int32_t>(o.cell_hubs.value_or(0))) {
    return "--participant-id " + std::to_string(*o.participant_id) + " is a hub's (hubs are 0 .. " +
           std::to_string(*o.cell_hubs - 1) + ")";
  }
  return std::nullopt;
}

int run_attach(AttachOptions o) {
  if (auto err = check_attach(o)) {
    spdlog::error("{}", *err);
    return 2;
  }
  if (o.cell_hubs) {
    // The monitor is a member of every hub's cell (runtime::bus_options reads these).
    bus::CellDiscovery cell;
    cell.domain = o.domain;
    for (uint32_t i = 0; i < *o.cell_hubs; ++i) cell.peers.push_back({"127.0.0.1", i});
    setenv(bus::kCellEnv, bus::format_cell(cell).c_str(), 1);
    if (o.participant_id) setenv("PHEROMESH_PARTICIPANT_ID", std::to_string(*o.participant_id).c_str(), 1);
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
