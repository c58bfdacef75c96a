// What the two ways of reaching a vendor share (make_bus.cpp links both
// vendors in; module_bus.cpp loads the one a process names): the error for a
// vendor this build does not have, the DDS modules' entry point and where a
// program finds them. Internal to the bus; never installed.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/transport.hpp"
#include "pheromesh/core/result.hpp"

namespace pheromesh::bus {

// "unknown DDS vendor 'x' (this build has: cyclone, fastdds)", or for
// "mixed" what it is for.
core::Error unknown_vendor(const std::string& vendor);

// --- DDS modules --------------------------------------------------------------
// A program loads its vendor's bus from a shared module (libpheromesh_dds_
// cyclone.so, libpheromesh_dds_fastdds.so) when it makes its bus, so that a
// process maps and relocates one vendor's libraries, not both
// (docs/benchmarks.md, "A lighter process"). A module exports one symbol,
// kTransportModuleSymbol, a function returning its TransportModule.

// Raised when TransportModule or BusOptions change shape.
inline constexpr std::uint32_t kTransportModuleAbi = 1;
inline constexpr const char* kTransportModuleSymbol = "pheromesh_transport_module";
// Folder of the modules, replacing the one beside the program.
inline constexpr const char* kModuleDirEnv = "PHEROMESH_DDS_MODULE_DIR";

struct TransportModule {
  std::uint32_t abi = kTransportModuleAbi;
  std::uint32_t options_size = sizeof(BusOptions);  // as the module was built
  const char* vendor = nullptr;
  core::Result<std::unique_ptr<Transport>> (*make)(const BusOptions&) = nullptr;
};

// "libpheromesh_dds_<vendor>.so".
std::string module_file_name(const std::string& vendor);

// The module of `vendor`: in `env_dir` when given (and non-empty), else in
// `exe_dir`/`relative_dir` (the layout of the build tree and of an install
// alike: bin/ and lib/pheromesh/).
std::filesystem::path module_path(const std::string& vendor, const std::optional<std::string>& env_dir,
                                  const std::filesystem::path& exe_dir, const std::string& relative_dir);

// Why `module` cannot serve `vendor` (null: it can), naming `path`.
std::optional<std::string> module_mismatch(const TransportModule* module, const std::string& vendor,
                                           const std::string& path);

// dlopens the module at `path` once per process (module_loader.cpp, its own
// library: pheromesh_bus_module_loader) and checks it serves `vendor`. The
// module stays loaded until the process ends: its transports' code is in it.
core::Result<const TransportModule*> load_transport_module(const std::string& vendor, const std::string& path);

}  // namespace pheromesh::bus
