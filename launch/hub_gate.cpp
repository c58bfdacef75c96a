#include "hub_gate.hpp"

#include <unistd.h>

#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <utility>

namespace pheromesh::cli {

namespace {

std::optional<uint16_t> hex_port(std::string_view hex) {
  if (hex.empty() || hex.size() > 4) return std::nullopt;
  uint32_t v = 0;
  for (const char c : hex) {
    uint32_t d = 0;
    if (c >= '0' && c <= '9') {
      d = static_cast<uint32_t>(c - '0');
    } else if (c >= 'A' && c <= 'F') {
      d = static_cast<uint32_t>(c - 'A' + 10);
    } else if (c >= 'a' && c <= 'f') {
      d = static_cast<uint32_t>(c - 'a' + 10);
    } else {
      return std::nullopt;
    }
    v = v * 16 + d;
  }
  return static_cast<uint16_t>(v);
}

// The whole file: with a thousand UAVs a namespace lists thousands of
// sockets, more than read_small_file's 64 KiB.
std::optional<std::string> read_whole(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

std::set<uint16_t> udp_local_ports(std::string_view text) {
  // "  12: 0100007F:1CE9 00000000:0000 07 ...": slot, local ADDRESS:PORT (hex).
  std::set<uint16_t> ports;
  std::istringstream lines{std::string(text)};
  std::string slot;
  std::string local;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    if (!(fields >> slot >> local) || slot.empty() || slot.back() != ':') continue;
    const std::size_t colon = local.rfind(':');
    if (colon == std::string::npos) continue;
    if (const auto port = hex_port(std::string_view(local).substr(colon + 1))) ports.insert(*port);
  }
  return ports;
}

std::optional<std::set<uint16_t>> udp_ports_of(pid_t pid) {
  const std::string base = "/proc/" + std::to_string(pid) + "/net/";
  auto v4 = read_whole(base + "udp");
  if (!v4) return std::nullopt;
  std::set<uint16_t> ports = udp_local_ports(*v4);
  if (const auto v6 = read_whole(base + "udp6")) ports.merge(udp_local_ports(*v6));
  return ports;
}

std::optional<std::string> net_namespace_of(pid_t pid) {
  const std::string link = "/proc/" + std::to_string(pid) + "/ns/net";
  char target[128];
  const ssize_t n = readlink(link.c_str(), target, sizeof target);
  if (n <= 0 || static_cast<std::size_t>(n) >= sizeof target) return std::nullopt;
  return std::string(target, static_cast<std::size_t>(n));
}

HubGate::PortsOf HubGate::ports_once_per_namespace() {
  auto read = std::make_shared<std::map<std::string, std::optional<std::set<uint16_t>>>>();
  return [read](pid_t pid) -> std::optional<std::set<uint16_t>> {
    const auto ns = net_namespace_of(pid);
    if (!ns) return std::nullopt;
    auto [it, fresh] = read->try_emplace(*ns);
    if (fresh) it->second = udp_ports_of(pid);
    return it->second;
  };
}

HubGate::HubGate(std::vector<AwaitedHub> hubs, Clock::time_point start, Clock::duration bound)
    : waiting_(std::move(hubs)), hubs_(waiting_.size()), deadline_(start + bound) {}

HubGate::Verdict HubGate::look(Clock::time_point now, const PortsOf& ports_of) {
  std::erase_if(waiting_, [&](const AwaitedHub& h) {
    const auto ports = ports_of(h.pid);
    if (!ports) {
      gone_.push_back(h.name);
      return true;
    }
    return ports->contains(h.port);
  });
  if (waiting_.empty()) return Verdict::Open;
  return now >= deadline_ ? Verdict::GaveUp : Verdict::Wait;
}

}  // namespace pheromesh::cli
