#include "pheromesh/bus/cell_discovery.hpp"

#include "dds_profiles.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>

#include <algorithm>
#include <optional>
#include <vector>

namespace pheromesh::bus {
namespace {

bool is_ipv4(const std::string& s) {
  in_addr a{};
  return inet_pton(AF_INET, s.c_str(), &a) == 1;
}

// The participant's data port (discovery port + 1) is the higher of its two.
core::Error port_error(const std::string& who, uint32_t domain, uint32_t index) {
  return core::Error{who + ": participant index " + std::to_string(index) + " of domain " + std::to_string(domain) +
                     " needs ports " + std::to_string(unicast_discovery_port(domain, index)) + "-" +
                     std::to_string(unicast_discovery_port(domain, index) + 1) + ", in the ephemeral range from " +
                     std::to_string(kEphemeralPortsFrom) + " (use a lower domain or index)"};
}

std::optional<core::Error> index_error(const std::string& who, uint32_t domain, uint32_t index) {
  if (index > kMaxParticipantIndex) {
    return core::Error{who + ": participant index " + std::to_string(index) + " is above " +
                       std::to_string(kMaxParticipantIndex) + " (Cyclone's limit, and the end of the domain's ports)"};
  }
  if (unicast_discovery_port(domain, index) + 1 >= kEphemeralPortsFrom) return port_error(who, domain, index);
  return std::nullopt;
}

}  // namespace

core::Result<CellDiscovery> check_cell(const CellDiscovery& cell) {
  if (cell.domain > kMaxDomainId) {
    return core::Error{"cell: domain " + std::to_string(cell.domain) + " is above " + std::to_string(kMaxDomainId)};
  }
  if (!is_ipv4(cell.interface_address)) {
    return core::Error{"cell: interface address '" + cell.interface_address + "' is not an IPv4 address"};
  }
  if (cell.index) {
    if (auto e = index_error("cell", cell.domain, *cell.index)) return *e;
  }
  for (const auto* list : {&cell.peers, &cell.reserve}) {
    for (const auto& p : *list) {
      const std::string who = std::string(list == &cell.peers ? "cell peer " : "cell reserve peer ") + p.address;
      if (!is_ipv4(p.address)) return core::Error{who + ": not an IPv4 address"};
      if (auto e = index_error(who, cell.domain, p.index)) return *e;
    }
  }
  return cell;
}

std::string format_cell(const CellDiscovery& cell) {
  std::string s = cell.index ? "index=" + std::to_string(*cell.index) + ";" : std::string();
  const auto list = [](const std::vector<CellPeer>& peers) {
    std::string l;
    for (std::size_t i = 0; i < peers.size(); ++i) {
      l += (i > 0 ? "," : "") + peers[i].address + ":" + std::to_string(peers[i].index);
    }
    return l;
  };
  s += "peers=" + list(cell.peers);
  if (!cell.reserve.empty()) s += ";reserve=" + list(cell.reserve);
  if (cell.interface_address != CellDiscovery{}.interface_address) s += ";iface=" + cell.interface_address;
  return s;
}

namespace {
std::optional<uint32_t> parse_index(const std::string& text) {
  if (text.empty() || text.size() > 6 || text.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  return static_cast<uint32_t>(std::stoul(text));
}
}  // namespace

core::Result<CellDiscovery> parse_cell(const std::string& text, uint32_t domain) {
  const auto bad = [&](const std::string& why) {
    return core::Error{std::string(kCellEnv) + " '" + text + "': " + why +
                       " (expected [index=I;]peers=ADDR:I[,ADDR:I...][;reserve=ADDR:I[,ADDR:I...]][;iface=ADDR])"};
  };
  CellDiscovery cell;
  cell.domain = domain;
  bool have_peers = false;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find(';', start), text.size());
    const std::string part = text.substr(start, end - start);
    start = end + 1;
    if (part.empty()) continue;
    const std::size_t eq = part.find('=');
    const std::string key = part.substr(0, eq);
    const std::string value = eq == std::string::npos ? std::string() : part.substr(eq + 1);
    if (key == "index") {
      auto i = parse_index(value);
      if (!i) return bad("index '" + value + "' is not a number");
      cell.index = *i;
    } else if (key == "iface") {
      cell.interface_address = value;
    } else if (key == "peers" || key == "reserve") {
      have_peers = have_peers || key == "peers";
      auto& into = key == "peers" ? cell.peers : cell.reserve;
      std::size_t p = 0;
      while (p < value.size()) {
        const std::size_t comma = std::min(value.find(',', p), value.size());
        const std::string peer = value.substr(p, comma - p);
        p = comma + 1;
        const std::size_t colon = peer.rfind(':');
        auto i = colon == std::string::npos ? std::nullopt : parse_index(peer.substr(colon + 1));
        if (!i) return bad("peer '" + peer + "' is not ADDR:INDEX");
        into.push_back({peer.substr(0, colon), *i});
      }
    } else {
      return bad("unknown part '" + key + "'");
    }
  }
  if (!have_peers) return bad("no peers");
  return check_cell(cell);
}

std::string cyclone_cell_config(const CellDiscovery& cell, uint32_t swarm_processes) {
  // ParticipantIndex none: a member's unicast ports come from the kernel, so
  // any number of members share a host and a domain (an index would cap them
  // at 120 per domain). Cyclone calls that "unicast discovery impossible",
  // meaning that nobody can find such a participant by its port: nobody needs
  // to, as the hub learns its locators from its announcement.
  const std::string index = cell.index ? std::to_string(*cell.index) : "none";
  std::string peers;
  // Cyclone gives a participant without multicast and without peers a
  // default peer, localhost at indices 0..MaxAutoParticipantIndex (9):
  // measured, two hubs of one domain (indices 0 and 1, no peers) discovered
  // each other. A hub without peers therefore names itself, which adds no
  // one.
  std::vector<CellPeer> named = cell.peers;
  if (named.empty() && cell.index) named.push_back({cell.interface_address, *cell.index});
  for (const auto& p : named) {
    // With a port, Cyclone sends to that one port, not to every index up to
    // MaxAutoParticipantIndex.
    peers +=
        "<Peer Address=\"" + p.address + ":" + std::to_string(unicast_discovery_port(cell.domain, p.index)) + "\"/>";
  }
  // SPDPInterval 5 s instead of Cyclone's 30 s: a member whose first
  // announcements went out before its hub listened (a Fast DDS hub starts
  // slower than a Cyclone member; a hub restarts) is otherwise found only
  // 30 s later (measured: 100 Cyclone members of Fast DDS hubs took 30.7 s,
  // 250 took 4.0 s). A hub has no peers to announce itself to, so only the
  // members' repeats bring it back. 5 s is Fast DDS's announcement period in
  // our profiles; it costs one datagram per member per 5 s.
  //
  // The settings besides discovery are cyclone-onehost-unicast.xml's, for
  // the same reasons (written there), its heartbeat interval among them. In
  // a cell it matters for the data, not discovery: Cyclone asks for an
  // acknowledgement with a write that comes 4/5 of an interval after the one
  // before, so at 100 ms every 5 Hz write of a keep-last writer (a UAV's
  // state, a batch of deposits, a halo) brought an ACKNACK back, one datagram
  // and a wake-up each. At 1 s the heartbeats that go with the writes are
  // final: a reader that misses a sample still asks for it (issue 44,
  // docs/benchmarks.md "Where a UAV tick goes").
  const std::string hb = cyclone_heartbeat(swarm_processes);
  return R"(<CycloneDDS xmlns="https://cdds.io/config"><Domain Id="any"><General><Interfaces><NetworkInterface address=")" +
         cell.interface_address +
         R"("/></Interfaces><AllowMulticast>false</AllowMulticast><MaxMessageSize>65500B</MaxMessageSize>)"
         R"(<MaxRexmitMessageSize>65500B</MaxRexmitMessageSize><FragmentSize>65000B</FragmentSize></General>)"
         R"(<Discovery><ParticipantIndex>)" +
         index + R"(</ParticipantIndex><SPDPInterval>5s</SPDPInterval><LeaseDuration>3600s</LeaseDuration>)" +
         (peers.empty() ? std::string() : "<Peers>" + peers + "</Peers>") +
         R"(</Discovery><Internal><WriterLingerDuration>0s</WriterLingerDuration>)"
         R"(<GenerateKeyhash>true</GenerateKeyhash><MultipleReceiveThreads>false</MultipleReceiveThreads>)"
         R"(<SocketReceiveBufferSize min="default" max="4MiB"/>)" +
         (hb.empty() ? std::string() : "<HeartbeatInterval>" + hb + "</HeartbeatInterval>") +
         R"(</Internal></Domain></CycloneDDS>)";
}

FastDdsCellProfile fastdds_cell_profile(const CellDiscovery& cell) {
  std::string name = "pheromesh-cell-d" + std::to_string(cell.domain) +
                     (cell.index ? "-i" + std::to_string(*cell.index) : std::string("-member"));
  for (const auto& p : cell.peers) name += "-" + p.address + "." + std::to_string(p.index);
  const std::string locator_open = "<locator><udpv4><address>";
  std::string peers;
  for (const auto& p : cell.peers) {
    peers += locator_open + p.address + "</address><port>" +
             std::to_string(unicast_discovery_port(cell.domain, p.index)) + "</port></udpv4></locator>";
  }
  // A hub's participant id fixes its ports; a member's comes from
  // BusOptions::participant_id or the search (mutation_tries, as onehost).
  const std::string id = cell.index ? "<participantID>" + std::to_string(*cell.index) + "</participantID>" : "";
  // A send buffer as large as the receive buffer (Fast DDS's default is the
  // system's, 208 KiB here). Fast DDS 2.9 also uses this size to pace the
  // heartbeats a reliable writer adds for all of its readers, and a hub's
  // discovery writers send every new member its ~100 endpoints. Measured
  // (pheromesh bench scale, Fast DDS UAVs in cells on 2 cores): discovery of
  // 100 UAVs 12.3 s -> 3.7 s, of 250 49-96 s -> 18 s, UDP datagrams per UAV
  // tick 117 -> 41. At 500 a member still gets ~15 heartbeats a second from
  // each hub's publications writer while the swarm joins (docs/dds.md,
  // "Cell discovery (measured)").
  // A metatraffic unicast locator and no multicast one: Fast DDS then opens
  // no multicast discovery socket and announces to the initial peers only.
  // An initial peer with a port is that port alone (port 0 would mean every
  // participant id up to maxInitialPeersRange).
  std::string xml = R"(<?xml version="1.0" encoding="UTF-8"?>)"
                    R"(<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles"><profiles>)"
                    R"(<transport_descriptors><transport_descriptor><transport_id>)" +
                    name +
                    R"(-udp</transport_id><type>UDPv4</type><sendBufferSize>4194304</sendBufferSize>)"
                    R"(<receiveBufferSize>4194304</receiveBufferSize>)"
                    R"(<interfaceWhiteList><address>)" +
                    cell.interface_address +
                    R"(</address></interfaceWhiteList>)"
                    R"(</transport_descriptor></transport_descriptors>)"
                    R"(<participant profile_name=")" +
                    name + R"("><rtps><userTransports><transport_id>)" + name +
                    R"(-udp</transport_id></userTransports><useBuiltinTransports>false</useBuiltinTransports>)" + id +
                    R"(<builtin><discovery_config><leaseDuration><sec>3600</sec></leaseDuration>)"
                    R"(<leaseAnnouncement><sec>5</sec></leaseAnnouncement></discovery_config>)"
                    R"(<avoid_builtin_multicast>true</avoid_builtin_multicast><metatrafficUnicastLocatorList>)" +
                    locator_open + cell.interface_address +
                    "</address></udpv4></locator></metatrafficUnicastLocatorList>" +
                    (peers.empty() ? std::string() : "<initialPeersList>" + peers + "</initialPeersList>") +
                    R"(<mutation_tries>120</mutation_tries></builtin></rtps></participant></profiles></dds>)";
  return {std::move(xml), std::move(name)};
}

}  // namespace pheromesh::bus
