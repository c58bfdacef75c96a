#include "launch/hosts_file.hpp"

#include <algorithm>
#include <cctype>

namespace pheromesh::cli {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())) != 0) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())) != 0) s.remove_suffix(1);
  return s;
}

std::string at_line(const std::string& path, uint32_t line) { return path + ":" + std::to_string(line) + ": "; }

// Why `word` cannot be an entry, or "" if it can: an IPv4 address or an RFC
// 1123 host name (letters, digits, '-' and '.'), no port, no list.
std::string malformed(std::string_view word) {
  if (word.find(',') != std::string_view::npos) return "one host per line, not a list";
  if (word.find(':') != std::string_view::npos) return "no port: every host uses the DDS ports of the domain";
  if (word.size() > 253 || word.front() == '.' || word.front() == '-' ||
      !std::all_of(word.begin(), word.end(),
                   [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '.'; })) {
    return "neither an IPv4 address nor a host name";
  }
  return "";
}

// One line's entry; nullopt for a blank or comment line.
core::Result<std::optional<HostsEntry>> entry_of(std::string_view raw, const std::string& path, uint32_t line,
                                                 const ResolveHost& resolve) {
  const std::string_view text = trim(raw.substr(0, raw.find('#')));
  if (text.empty()) return std::optional<HostsEntry>();
  const std::string where = at_line(path, line) + "'" + std::string(text) + "': ";
  if (std::any_of(text.begin(), text.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; })) {
    return core::Error{where + "one host per line (an address or a name, then at most a # comment)"};
  }
  if (const std::string why = malformed(text); !why.empty()) return core::Error{where + why};
  const std::string name(text);
  auto addresses = resolve(name);
  if (!addresses) return core::Error{where + addresses.error().message};
  if (addresses->empty()) return core::Error{where + "does not resolve"};
  if (addresses->size() > 1) {
    std::string list;
    for (const auto& a : addresses.value()) list += (list.empty() ? "" : ", ") + a;
    return core::Error{where + "resolves to " + std::to_string(addresses->size()) + " addresses (" + list +
                       "); each line names one host: write its address"};
  }
  return std::optional<HostsEntry>(HostsEntry{name, addresses->front(), line});
}

}  // namespace

core::Result<HostsFile> parse_hosts_file(std::string_view text, const std::string& path, const ResolveHost& resolve) {
  HostsFile file{path, {}};
  uint32_t line = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    ++line;
    auto entry = entry_of(text.substr(start, end - start), path, line, resolve);
    start = end + 1;
    if (!entry) return entry.error();
    if (!entry->has_value()) continue;
    const HostsEntry& e = *entry.value();
    const auto same =
        std::find_if(file.hosts.begin(), file.hosts.end(), [&](const HostsEntry& h) { return h.address == e.address; });
    if (same != file.hosts.end()) {
      return core::Error{at_line(path, line) + "'" + e.name + "' is " + e.address + ", as line " +
                         std::to_string(same->line) + " ('" + same->name + "', host " +
                         std::to_string(same - file.hosts.begin()) + ") is: every host once"};
    }
    file.hosts.push_back(e);
  }
  if (file.hosts.empty()) {
    return core::Error{path + ": no host in it (one address or name per line, in host-index order)"};
  }
  return file;
}

namespace {

std::string joined_addresses(const HostsFile& file) {
  std::string out;
  for (const auto& h : file.hosts) out += (out.empty() ? "" : ",") + h.address;
  return out;
}

std::string entry_text(const HostsFile& file, std::size_t i) {
  const HostsEntry& h = file.hosts[i];
  return "host " + std::to_string(i) + " (line " + std::to_string(h.line) + ", " +
         (h.name == h.address ? h.address : h.name + " = " + h.address) + ")";
}

// --host-index left out: the one entry that is an address of this host.
core::Result<uint32_t> this_host(const HostsFile& file, const IsLocalAddress& is_local) {
  std::vector<std::size_t> mine;
  for (std::size_t i = 0; i < file.hosts.size(); ++i) {
    if (is_local(file.hosts[i].address)) mine.push_back(i);
  }
  if (mine.size() == 1) return static_cast<uint32_t>(mine.front());
  if (mine.empty()) {
    return core::Error{"--hosts-file " + file.path + ": no entry is an address of this host; give --host-index, or " +
                       "list this host by an address one of its interfaces has"};
  }
  std::string which;
  for (const std::size_t i : mine) which += (which.empty() ? "" : ", ") + entry_text(file, i);
  return core::Error{"--hosts-file " + file.path + ": several entries are addresses of this host (" + which +
                     "); give --host-index"};
}

}  // namespace

core::Result<HostsChoice> choose_host(const HostsFile& file, const HostsFlags& flags, const IsLocalAddress& is_local) {
  const std::string given = "--hosts-file " + file.path + " gives ";
  if (flags.hosts) {
    return core::Error{given + "--hosts (" + std::to_string(file.hosts.size()) + " hosts): leave --hosts " +
                       std::to_string(*flags.hosts) + " out"};
  }
  if (!flags.dds_peers.empty()) {
    return core::Error{given + "--dds-peers (every host's address, in its order): leave " + flags.dds_peers_from +
                       " (" + flags.dds_peers + ") out"};
  }
  HostsChoice c;
  c.hosts = static_cast<uint32_t>(file.hosts.size());
  c.dds_peers = joined_addresses(file);
  if (flags.host_index) {
    if (*flags.host_index >= c.hosts) {
      return core::Error{"--host-index " + std::to_string(*flags.host_index) + " is not below the " +
                         std::to_string(c.hosts) + " hosts of --hosts-file " + file.path};
    }
    c.host_index = *flags.host_index;
    return c;
  }
  auto mine = this_host(file, is_local);
  if (!mine) return mine.error();
  c.host_index = mine.value();
  return c;
}

core::Result<std::string> attach_peers(const HostsFile& file, const HostsFlags& flags) {
  if (!flags.dds_peers.empty()) {
    return core::Error{"--hosts-file " + file.path + " gives --dds-peers (every host's address): leave " +
                       flags.dds_peers_from + " (" + flags.dds_peers + ") out"};
  }
  return joined_addresses(file);
}

}  // namespace pheromesh::cli
