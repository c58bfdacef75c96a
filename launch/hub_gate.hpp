// In cells a member (a UAV) announces itself to its hubs (the ground station
// and its home place agents) and they do not announce themselves to it: a
// hub learns a member from the member's announcement. An announcement sent
// before the hub listens is lost, and the member repeats it only at its
// discovery interval, 5 s (bus/cell_discovery.cpp). A Cyclone UAV starts in
// a few tens of milliseconds, a Fast DDS hub takes longer: a swarm launched
// at once lost its first announcements to the slower hubs, and such a UAV
// was heard 5 s late (a mixed swarm on a slow host: discovery 6.4 s instead
// of under 1 s).
//
// So the launcher starts the members of a host once that host's hubs listen:
// once each hub's unicast discovery port is bound in its network namespace
// (/proc/PID/net/udp). A hub that ends before is not waited for (the
// launcher reports it), and after a bound the members start anyway.
//
// Pure but for udp_ports_of: the gate takes the time and the ports it is
// given (tests/unit/test_hub_gate.cpp).
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace pheromesh::cli {

// The local ports of the sockets a /proc/net/udp (or udp6) text lists; the
// header line and lines that do not parse are skipped.
std::set<uint16_t> udp_local_ports(std::string_view proc_net_udp);

// The UDP ports bound in process `pid`'s network namespace (/proc/PID/net/udp
// and udp6), or nothing if the process is gone.
std::optional<std::set<uint16_t>> udp_ports_of(pid_t pid);

// The network namespace of process `pid` (the link /proc/PID/ns/net, as
// "net:[4026531840]"), or nothing if it is gone.
std::optional<std::string> net_namespace_of(pid_t pid);

struct AwaitedHub {
  std::string name;   // its process name, for the log
  pid_t pid = 0;      // a process of this host
  uint16_t port = 0;  // its unicast discovery port (bus::unicast_discovery_port)
};

class HubGate {
 public:
  using Clock = std::chrono::steady_clock;
  // The UDP ports bound where `pid` runs, or nothing if it is gone.
  using PortsOf = std::function<std::optional<std::set<uint16_t>>(pid_t)>;
  enum class Verdict : uint8_t { Wait, Open, GaveUp };

  HubGate(std::vector<AwaitedHub> hubs, Clock::time_point start, Clock::duration bound);

  // One look at the hubs not yet heard listening: Open once none is left
  // (listening or gone), else GaveUp from `start` + `bound` on, else Wait.
  Verdict look(Clock::time_point now, const PortsOf& ports_of);

  [[nodiscard]] const std::vector<AwaitedHub>& waiting() const { return waiting_; }
  // Hubs that ended before they were seen listening, by name.
  [[nodiscard]] const std::vector<std::string>& gone() const { return gone_; }
  [[nodiscard]] std::size_t hubs() const { return hubs_; }

  // udp_ports_of for one look: every hub of one network namespace sees the
  // same table, so each namespace is read once (a hundred place agents on
  // one host: one read, not a hundred).
  [[nodiscard]] static PortsOf ports_once_per_namespace();

 private:
  std::vector<AwaitedHub> waiting_;
  std::vector<std::string> gone_;
  std::size_t hubs_ = 0;
  Clock::time_point deadline_;
};

}  // namespace pheromesh::cli
