// The shell of hosts_file.hpp: the file read, its names resolved as
// --dds-peers' are (bus::resolve_peers).
#include <fstream>
#include <sstream>

#include "launch/hosts_file.hpp"
#include "pheromesh/bus/bus.hpp"

namespace pheromesh::cli {

core::Result<HostsFile> read_hosts_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return core::Error{"--hosts-file " + path + ": cannot be read"};
  std::stringstream text;
  text << in.rdbuf();
  return parse_hosts_file(text.str(), path, [](const std::string& entry) -> core::Result<std::vector<std::string>> {
    auto r = bus::resolve_peers(entry);
    if (!r) return r.error();
    return std::move(r->addresses);
  });
}

}  // namespace pheromesh::cli
