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
  std::string dds_profile = "onehost";
  std::string dds_peers;
  std::string out_dir = "out/attach";
  std::optional<uint16_t> http_port;
  std::string http_bind = "127.0.0.1";
  std::string record;
  double timeout_s = 60;
  double progress_s = 1.0;
  std::string log_level = "info";
  std::string secure;  // DDS Security directory: the monitor uses its read-only identity there
  // --dds-profile cells: the swarm's hubs (the ground station and every
  // place agent replica, indices 0 .. cell_hubs - 1 on loopback), which the
  // monitor names as its peers; and a Fast DDS monitor's participant id, past
  // every UAV's (`pheromesh run` prints both).
  std::optional<uint32_t> cell_hubs;
  std::optional<int32_t> participant_id;
};

// Why these options cannot reach a swarm, if they cannot: an error message.
std::optional<std::string> check_attach(const AttachOptions& o);

// Replaces this process with pheromesh-ground --attach; returns only on error.
int run_attach(AttachOptions o);

}  // namespace pheromesh::cli
