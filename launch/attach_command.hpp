// `pheromesh attach`: a monitor for a running swarm, found by its domain id
// alone (pheromesh-ground --attach; docs/deployment.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace pheromesh::cli {

struct AttachOptions {
  uint32_t domain = 0;
  std::string dds;
  std::string dds_profile = "cells";  // as `pheromesh run`'s default
  std::string dds_peers;
  std::string dds_peers_from;  // "--dds-peers" or "$PHEROMESH_DDS_PEERS" when dds_peers came from one
  std::string hosts_file;      // --hosts-file (hosts_file.hpp): stands for --dds-peers
  std::string out_dir = "out/attach";
  std::optional<uint16_t> http_port;
  std::string http_bind = "127.0.0.1";
  std::string record;
  std::string mavlink;           // stream to a MAVLink station, "udp:HOST:PORT" (docs/mavlink.md); empty: none
  double mavlink_rate_hz = 4.0;  // [Hz]
  double timeout_s = 60;
  double progress_s = 1.0;
  std::string log_level = "info";
  std::string secure;  // DDS Security directory: the monitor uses its read-only identity there
  // --dds-profile cells: the most hubs (the ground station and place agent
  // replicas) on one host of the swarm: the monitor names indices 0 ..
  // cell_hubs - 1 on every host of --dds-peers (loopback without), all 120
  // if not given (`pheromesh run` prints the number). A Fast DDS monitor's
  // participant id: by default the domain's highest below the ephemeral
  // ports, past every hub's and UAV's.
  std::optional<uint32_t> cell_hubs;
  std::optional<int32_t> participant_id;
};

// A Fast DDS monitor's participant id in cells if none is given: the
// highest whose ports on `domain` stay below the ephemeral range.
uint32_t default_monitor_participant_id(uint32_t domain);

// Why these options cannot reach a swarm, if they cannot: an error message.
std::optional<std::string> check_attach(const AttachOptions& o);

// Replaces this process with pheromesh-ground --attach; returns only on error.
int run_attach(AttachOptions o);

}  // namespace pheromesh::cli
