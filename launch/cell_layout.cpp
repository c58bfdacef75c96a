#include "cell_layout.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <functional>

#include "pheromesh/core/messages.hpp"

namespace pheromesh::cli {
namespace {

constexpr const char* kLoopback = "127.0.0.1";

// A UDP socket, closed when it goes out of scope.
class UdpSocket {
 public:
  UdpSocket() : fd_(socket(AF_INET, SOCK_DGRAM, 0)) {}
  ~UdpSocket() {
    if (fd_ >= 0) close(fd_);
  }
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;
  [[nodiscard]] int fd() const { return fd_; }

 private:
  int fd_;
};

std::optional<sockaddr_in> ipv4(const std::string& address, uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  if (inet_pton(AF_INET, address.c_str(), &a.sin_addr) != 1) return std::nullopt;
  return a;
}

}  // namespace

CellLayout::CellLayout(SwarmShape shape) : s_(std::move(shape)) {
  s_.hosts = std::max(1U, s_.hosts);
  s_.regions = std::max(1U, s_.regions);
  s_.replicas = std::max(1U, s_.replicas);
}

uint32_t CellLayout::host_of(const std::string& role, uint32_t index, uint32_t replica) const {
  if (s_.hosts <= 1) return 0;
  if (role == "ground") return s_.ground_host;
  if (role == "place") return (index + replica) % s_.hosts;
  if (auto pin = s_.uav_hosts.find(index); pin != s_.uav_hosts.end()) return pin->second;
  // A UAV flies beside its home place agent's primary.
  return host_of("place", core::home_region(index, s_.regions), 0);
}

std::string CellLayout::address_of(uint32_t host) const {
  return host < s_.addresses.size() ? s_.addresses[host] : std::string(kLoopback);
}

bus::CellPeer CellLayout::hub(const std::string& role, uint32_t index, uint32_t replica) const {
  if (role == "ground") return {address_of(s_.ground_host), 0};
  const uint32_t host = host_of("place", index, replica);
  // The ground station first, then the replicas of this host by (replica,
  // region): the order their indices follow.
  uint32_t i = host == s_.ground_host ? 1 : 0;
  for (uint32_t k = 0; k < s_.replicas; ++k) {
    for (uint32_t r = 0; r < s_.regions; ++r) {
      if (k == replica && r == index) return {address_of(host), i};
      if (host_of("place", r, k) == host) ++i;
    }
  }
  return {address_of(host), i};
}

uint32_t CellLayout::hubs_on(uint32_t host) const {
  uint32_t n = host == s_.ground_host ? 1 : 0;
  for (uint32_t k = 0; k < s_.replicas; ++k) {
    for (uint32_t r = 0; r < s_.regions; ++r) n += host_of("place", r, k) == host ? 1 : 0;
  }
  return n;
}

uint32_t CellLayout::most_hubs_on_a_host() const {
  uint32_t most = 0;
  for (uint32_t h = 0; h < s_.hosts; ++h) most = std::max(most, hubs_on(h));
  return most;
}

namespace {

// Who names whom, wherever the hubs are (`hub` finds one): a UAV its home
// place agent's replicas (and its backup's: as reserve in realtime), a hub
// every other hub; a monitor every hub.
bus::CellDiscovery cell_naming(const SwarmShape& s, const std::string& role, uint32_t index, uint32_t replica,
                               const std::function<bus::CellPeer(const std::string&, uint32_t, uint32_t)>& hub) {
  bus::CellDiscovery c;
  c.domain = s.domain;
  const auto add_place = [&](core::RegionId r, std::vector<bus::CellPeer>& to) {
    for (uint32_t k = 0; k < s.replicas; ++k) to.push_back(hub("place", r, k));
  };
  if (role == "uav") {
    const core::RegionId home = core::home_region(index, s.regions);
    const core::RegionId backup = core::backup_region(index, s.regions);
    add_place(home, c.peers);
    // A realtime UAV names its backup gateway only once its home is gone
    // (reserve): discovered ahead, every place agent's cell held its backup
    // UAVs too, and 500 UAVs in 16 cells took 80-90 s to discover on Fast
    // DDS instead of 16 s (Cyclone 44-75 s instead of 11 s). A lockstep UAV
    // hears of its home's death in the clock, which the backup relays to
    // it, so it names the backup from the start.
    if (backup != home) add_place(backup, s.lockstep ? c.peers : c.reserve);
    return c;
  }
  if (role != "monitor") c.index = hub(role, index, replica).index;
  // Hubs name one another: the ground station every place agent, a place
  // agent the ground station and every other place agent (not itself); a
  // monitor is a member of every hub's cell.
  if (role != "ground") c.peers.push_back(hub("ground", 0, 0));
  for (core::RegionId r = 0; r < s.regions; ++r) {
    for (uint32_t k = 0; k < s.replicas; ++k) {
      if (role == "place" && r == index && k == replica) continue;
      c.peers.push_back(hub("place", r, k));
    }
  }
  return c;
}

}  // namespace

bus::CellDiscovery CellLayout::cell_of(const std::string& role, uint32_t index, uint32_t replica) const {
  auto c = cell_naming(s_, role, index, replica,
                       [this](const std::string& r, uint32_t i, uint32_t k) { return hub(r, i, k); });
  c.interface_address = address_of(host_of(role, index, replica));
  return c;
}

std::optional<std::string> CellLayout::check(bool fastdds_members) const {
  for (uint32_t h = 0; h < s_.hosts; ++h) {
    const uint32_t hubs = hubs_on(h);
    if (hubs > bus::kMaxParticipantIndex + 1) {
      return "cells: host " + std::to_string(h) + " would run " + std::to_string(hubs) +
             " place agents (with standbys) and ground stations, which need participant indices 0.." +
             std::to_string(hubs - 1) + ", above " + std::to_string(bus::kMaxParticipantIndex) +
             " (Cyclone's limit): use fewer regions or more hosts";
    }
  }
  // The highest hub index of any host is the one to check: the others'
  // ports are lower.
  for (uint32_t k = 0; k < s_.replicas; ++k) {
    for (uint32_t r = 0; r < s_.regions; ++r) {
      if (auto err = bus::check_cell(cell_of("place", r, k)); !err) return err.error().message;
    }
  }
  if (s_.uavs > 0) {
    if (auto err = bus::check_cell(cell_of("uav", s_.uavs - 1)); !err) return err.error().message;
  }
  // A Fast DDS UAV's ports follow its id: below the ephemeral range too.
  if (s_.uavs > 0 && fastdds_members) {
    const uint32_t last = member_id(s_.uavs - 1);
    if (bus::unicast_discovery_port(s_.domain, last) + 1 >= bus::kEphemeralPortsFrom) {
      return "cells: Fast DDS UAV " + std::to_string(s_.uavs - 1) + " would take participant id " +
             std::to_string(last) + ", whose ports on domain " + std::to_string(s_.domain) +
             " reach the ephemeral range from " + std::to_string(bus::kEphemeralPortsFrom) +
             ": use a lower --domain or fewer UAVs";
    }
  }
  return std::nullopt;
}

core::Result<std::map<uint32_t, uint32_t>> parse_uav_pins(const std::string& text, uint32_t uavs, uint32_t hosts) {
  std::map<uint32_t, uint32_t> pins;
  if (text.empty()) return pins;
  if (hosts <= 1) {
    return core::Error{"--pin-uavs " + text + ": pins place UAVs on the hosts of --hosts; this swarm has one host"};
  }
  const auto number = [](const std::string& s) -> std::optional<uint32_t> {
    if (s.empty() || s.size() > 9 || s.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
    return static_cast<uint32_t>(std::stoul(s));
  };
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    start = comma + 1;
    const auto bad = [&](const std::string& why) {
      return core::Error{"--pin-uavs: '" + item + "': " + why +
                         " (expected U=H or A-B=H, comma-separated: UAV ids, "
                         "host indices)"};
    };
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos) return bad("no '='");
    const std::string ids = item.substr(0, eq);
    const std::size_t dash = ids.find('-');
    const auto first = number(ids.substr(0, dash));
    const auto last = dash == std::string::npos ? first : number(ids.substr(dash + 1));
    const auto host = number(item.substr(eq + 1));
    if (!first || !last) return bad("the UAV ids are not numbers");
    if (!host) return bad("the host is not a number");
    if (*last < *first) return bad("the range runs backwards");
    if (*last >= uavs) return bad("the swarm's UAVs are 0.." + std::to_string(uavs - 1));
    if (*host >= hosts) return bad("the hosts are 0.." + std::to_string(hosts - 1));
    for (uint32_t u = *first; u <= *last; ++u) {
      if (!pins.emplace(u, *host).second) return bad("UAV " + std::to_string(u) + " is pinned twice");
    }
    if (comma == text.size()) break;
  }
  return pins;
}

std::optional<std::string> check_hub_names(const HubNames& names) {
  for (const auto& [what, name] : {std::pair{"place", &names.place}, std::pair{"ground", &names.ground}}) {
    if (name->empty()) return std::string(what) + " name: empty";
    for (std::size_t at = name->find('{'); at != std::string::npos; at = name->find('{', at + 1)) {
      if (what == std::string("place") && name->compare(at, 8, "{region}") == 0) continue;
      return std::string(what) + " name '" + *name + "': unknown placeholder at '" + name->substr(at) + "'" +
             (what == std::string("place") ? " (only {region} is known)" : " (the ground station's name has none)");
    }
  }
  if (names.place.find("{region}") == std::string::npos) {
    return "place name '" + names.place + "' has no {region}: every region's place agent needs a name of its own";
  }
  return std::nullopt;
}

std::string hub_name(const HubNames& names, const std::string& role, uint32_t region) {
  if (role == "ground") return names.ground;
  std::string out = names.place;
  const std::string number = std::to_string(region);
  for (std::size_t at = out.find("{region}"); at != std::string::npos; at = out.find("{region}", at + number.size())) {
    out.replace(at, 8, number);
  }
  return out;
}

bus::CellDiscovery named_cell(const SwarmShape& shape, const HubNames& names, const std::string& role, uint32_t index) {
  SwarmShape s = shape;
  s.regions = std::max(1U, s.regions);
  s.replicas = 1;
  auto c = cell_naming(s, role, index, 0, [&](const std::string& r, uint32_t i, uint32_t) {
    return bus::CellPeer{hub_name(names, r, i), 0};
  });
  c.interface_address.clear();
  return c;
}

bus::CellDiscovery monitor_cell(uint32_t domain, uint32_t hubs, const std::vector<std::string>& addresses,
                                const std::string& interface_address) {
  bus::CellDiscovery cell;
  cell.domain = domain;
  cell.interface_address = interface_address;
  const std::vector<std::string> hosts = addresses.empty() ? std::vector<std::string>{kLoopback} : addresses;
  for (const auto& a : hosts) {
    for (uint32_t i = 0; i < hubs; ++i) cell.peers.push_back({a, i});
  }
  return cell;
}

std::optional<std::string> local_address_towards(const std::string& peer) {
  auto to = ipv4(peer, 9);  // any port: connect() on UDP only picks a route
  if (!to) return std::nullopt;
  UdpSocket s;
  if (s.fd() < 0 || connect(s.fd(), reinterpret_cast<const sockaddr*>(&*to), sizeof *to) != 0) return std::nullopt;
  sockaddr_in me{};
  socklen_t len = sizeof me;
  if (getsockname(s.fd(), reinterpret_cast<sockaddr*>(&me), &len) != 0) return std::nullopt;
  char text[INET_ADDRSTRLEN] = {};
  if (inet_ntop(AF_INET, &me.sin_addr, text, sizeof text) == nullptr) return std::nullopt;
  return std::string(text);
}

bool is_local_address(const std::string& address) {
  auto at = ipv4(address, 0);
  if (!at) return false;
  UdpSocket s;
  return s.fd() >= 0 && bind(s.fd(), reinterpret_cast<const sockaddr*>(&*at), sizeof *at) == 0;
}

}  // namespace pheromesh::cli
