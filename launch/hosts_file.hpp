// A swarm's hosts in a file (`--hosts-file FILE` of `pheromesh run` and
// `pheromesh attach`; docs/deployment.md): one host per line, an IPv4
// address or a host name, the line order being the host index; `#` starts a
// comment, blank lines are ignored. It stands for `--hosts` (the number of
// entries) and `--dds-peers` (every entry, in order); `--host-index` still
// names this host, or, left out, the one entry that is an address of this
// host is taken.
//
// Pure: the file's text is passed in, and so are name resolution (the
// launcher's: bus::resolve_peers, one entry at a time) and the test of
// whether an address is this host's. Every refusal names the file and, for
// an entry, its line.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pheromesh/core/result.hpp"

namespace pheromesh::cli {

struct HostsEntry {
  std::string name;     // as written: an address or a host name
  std::string address;  // the IPv4 address it resolves to
  uint32_t line = 0;    // 1-based
};

struct HostsFile {
  std::string path;
  std::vector<HostsEntry> hosts;  // index = host index
};

// Every IPv4 address of one entry (empty: it does not resolve); an error for
// an entry that is neither an address nor a host name.
using ResolveHost = std::function<core::Result<std::vector<std::string>>(const std::string& entry)>;
// Whether an address is one of this host's.
using IsLocalAddress = std::function<bool(const std::string& address)>;

// Parses `text`, the contents of `path`. Refused: a file with no entry, a
// line of more than one word or with a port or a comma, an entry that is
// neither an IPv4 address nor a host name, a name that does not resolve or
// resolves to several addresses, and an entry whose address another line
// has already given.
core::Result<HostsFile> parse_hosts_file(std::string_view text, const std::string& path, const ResolveHost& resolve);

// What the command line gave besides --hosts-file.
struct HostsFlags {
  std::optional<uint32_t> hosts;       // --hosts
  std::optional<uint32_t> host_index;  // --host-index
  std::string dds_peers;               // --dds-peers or $PHEROMESH_DDS_PEERS
  std::string dds_peers_from;          // which of the two, for the message
};

// What the file stands for on this host.
struct HostsChoice {
  uint32_t hosts = 0;
  uint32_t host_index = 0;
  std::string dds_peers;  // every entry's address, comma-separated, in host-index order
};

// `pheromesh run --hosts-file`: refuses --hosts or --dds-peers given as well
// (the file gives both), a --host-index past the file's entries, and, without
// --host-index, no entry or several entries being addresses of this host.
core::Result<HostsChoice> choose_host(const HostsFile& file, const HostsFlags& flags, const IsLocalAddress& is_local);

// `pheromesh attach --hosts-file`: the peers, refusing --dds-peers given as well.
core::Result<std::string> attach_peers(const HostsFile& file, const HostsFlags& flags);

// The shell (hosts_file_io.cpp, not pure): the file at `path` read and its
// names resolved as --dds-peers' are (bus::resolve_peers).
core::Result<HostsFile> read_hosts_file(const std::string& path);

}  // namespace pheromesh::cli
