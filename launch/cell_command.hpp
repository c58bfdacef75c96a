// `pheromesh cell`: the cell of one process that runs alone at an address of
// its own (a container, a pod, a host per process), its hubs named by
// templates (cell_layout.hpp, HubNames). It prints the environment the
// process reads ($PHEROMESH_CELL, and for a member a Fast DDS participant
// id); deploy/container/entrypoint.sh runs it before each process in cells
// (docs/deploy-containers.md).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <CLI/CLI.hpp>

#include "cell_layout.hpp"
#include "pheromesh/core/result.hpp"

namespace pheromesh::cli {

struct CellCommandOptions {
  std::string role;               // place | uav | ground | monitor
  std::optional<uint32_t> index;  // place: region, uav: id
  std::string scenario;
  uint32_t domain = 0;
  std::string clock = "realtime";
  HubNames names;
  double wait_s = 120;  // how long names may take to resolve (pods that start together)
};

// One IPv4 address per name, or why not; nullopt: the name does not resolve
// (yet).
using NameResolver = std::function<core::Result<std::optional<std::vector<std::string>>>(const std::string& name)>;

// `named` with every peer's name replaced by its address (one pass, no
// waiting): the cell, or the names that do not resolve yet, or an error (a
// name with several addresses; two hubs at one address, whose index 0 would
// be taken twice). The interface address is the one `route` gives towards
// the first peer (this host's own if the cell has no peer).
struct Unresolved {
  std::vector<std::string> names;
};
core::Result<std::variant<bus::CellDiscovery, Unresolved>> resolve_named_cell(
    const bus::CellDiscovery& named, const NameResolver& resolve,
    const std::function<std::optional<std::string>(const std::string&)>& route);

// The lines `pheromesh cell` prints: NAME=VALUE, one per line.
std::vector<std::string> cell_environment(const std::string& role, const bus::CellDiscovery& cell);

CLI::App* add_cell_command(CLI::App& app, CellCommandOptions& o);
int run_cell_command(const CellCommandOptions& o);

}  // namespace pheromesh::cli
