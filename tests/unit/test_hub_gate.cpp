// The launcher starts a host's UAVs once that host's hubs listen
// (launch/hub_gate.hpp): the ports read from /proc, and the gate's verdicts
// with the time and the ports given.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <map>

#include "launch/hub_gate.hpp"
#include "pheromesh/bus/cell_discovery.hpp"

namespace pheromesh::cli {
namespace {

using namespace std::chrono_literals;
using GateClock = HubGate::Clock;

TEST(HubGate, TheLocalPortsOfAProcNetUdpTextAreReadInHex) {
  // Two IPv4 sockets (7410 = 0x1CF2 on 127.0.0.1, 53 = 0x35 on any), as the kernel prints them.
  const std::string v4 =
      "   sl  local_address rem_address   st tx_queue rx_queue tr tm->when retrnsmt   uid  timeout inode ref pointer "
      "drops\n"
      "  145: 0100007F:1CF2 00000000:0000 07 00000000:00000000 00:00000000 00000000     0        0 81234 2 "
      "0000000000000000 0\n"
      " 2010: 00000000:0035 00000000:0000 07 00000000:00000000 00:00000000 00000000     0        0 1234 2 "
      "0000000000000000 0\n";
  EXPECT_EQ(udp_local_ports(v4), (std::set<uint16_t>{7410, 53}));
  // IPv6: a 32-digit address, the same port field.
  const std::string v6 =
      "  sl  local_address                         remote_address                        st\n"
      "   3: 00000000000000000000000001000000:FFFF 00000000000000000000000000000000:0000 07 00000000:00000000\n";
  EXPECT_EQ(udp_local_ports(v6), (std::set<uint16_t>{65535}));
  // Nothing that does not parse: an empty text, a header, a port that is not hex.
  EXPECT_TRUE(udp_local_ports("").empty());
  EXPECT_TRUE(udp_local_ports("   sl  local_address rem_address\n").empty());
  EXPECT_TRUE(udp_local_ports("   1: 0100007F:1G00 00000000:0000 07\n").empty());
}

// A UDP socket on loopback at a port the kernel chose; closed at the end of
// its scope or by close().
class HubGateSocket {
 public:
  HubGateSocket() {
    fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) return;
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    if (bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
        getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len) == 0) {
      port_ = ntohs(a.sin_port);
    }
  }
  ~HubGateSocket() { close(); }
  HubGateSocket(const HubGateSocket&) = delete;
  HubGateSocket& operator=(const HubGateSocket&) = delete;
  HubGateSocket(HubGateSocket&&) = delete;
  HubGateSocket& operator=(HubGateSocket&&) = delete;
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  // 0 if it could not be bound.
  [[nodiscard]] uint16_t port() const { return port_; }

 private:
  int fd_ = -1;
  uint16_t port_ = 0;
};

TEST(HubGate, ThisProcesssBoundSocketIsSeenAndNotOnceClosed) {
  HubGateSocket sock;
  const auto port = sock.port();
  ASSERT_NE(port, 0);
  const auto bound = udp_ports_of(getpid());
  ASSERT_TRUE(bound.has_value());
  EXPECT_TRUE(bound->contains(port)) << port;
  sock.close();
  EXPECT_FALSE(udp_ports_of(getpid())->contains(port)) << port;
  // A process that does not exist has no ports to read.
  EXPECT_FALSE(udp_ports_of(0x3fffffff).has_value());
}

TEST(HubGate, PortsAreReadOncePerNetworkNamespaceAndAGoneProcessHasNone) {
  const auto own = net_namespace_of(getpid());
  ASSERT_TRUE(own.has_value());
  EXPECT_EQ(own->rfind("net:[", 0), 0U) << *own;
  EXPECT_EQ(net_namespace_of(getppid()), own) << "the test runner shares this namespace";
  EXPECT_FALSE(net_namespace_of(0x3fffffff).has_value());
  // Within one look a socket bound after the namespace was read is not seen:
  // the table was read once; the next look's reader reads it again.
  const auto look = HubGate::ports_once_per_namespace();
  const auto before = look(getpid());
  ASSERT_TRUE(before.has_value());
  HubGateSocket sock;
  const auto port = sock.port();
  ASSERT_NE(port, 0);
  EXPECT_FALSE(look(getppid())->contains(port)) << "the same namespace: the table read for the first pid";
  EXPECT_TRUE(HubGate::ports_once_per_namespace()(getppid())->contains(port));
  EXPECT_FALSE(look(0x3fffffff).has_value());
}

// The ports each pid has bound, as the test sets them; a pid not in the map is gone.
struct HubGatePorts {
  std::map<pid_t, std::set<uint16_t>> bound;
  [[nodiscard]] HubGate::PortsOf reader() const {
    return [this](pid_t pid) -> std::optional<std::set<uint16_t>> {
      const auto it = bound.find(pid);
      if (it == bound.end()) return std::nullopt;
      return it->second;
    };
  }
};

TEST(HubGate, ItOpensOnceEveryHubListensOnItsOwnDiscoveryPort) {
  const uint16_t ground = bus::unicast_discovery_port(43, 0);  // 7400 + 250 * 43 + 10 + 2 * 0
  const uint16_t place = bus::unicast_discovery_port(43, 1);
  ASSERT_EQ(ground, 18160);
  ASSERT_EQ(place, 18162);
  const auto t0 = GateClock::time_point{} + 1h;
  HubGate gate({{"ground", 10, ground}, {"place-0", 11, place}}, t0, 20s);
  HubGatePorts ports;
  ports.bound = {{10, {}}, {11, {}}};
  EXPECT_EQ(gate.look(t0, ports.reader()), HubGate::Verdict::Wait);
  EXPECT_EQ(gate.waiting().size(), 2U);
  // The ground station listens; the place agent has bound another port only.
  ports.bound[10] = {ground, 18161};
  ports.bound[11] = {ground + 100};
  EXPECT_EQ(gate.look(t0 + 100ms, ports.reader()), HubGate::Verdict::Wait);
  ASSERT_EQ(gate.waiting().size(), 1U);
  EXPECT_EQ(gate.waiting().front().name, "place-0");
  // Once seen listening a hub is not looked at again.
  ports.bound[10] = {};
  ports.bound[11] = {place};
  EXPECT_EQ(gate.look(t0 + 200ms, ports.reader()), HubGate::Verdict::Open);
  EXPECT_TRUE(gate.waiting().empty());
  EXPECT_TRUE(gate.gone().empty());
  EXPECT_EQ(gate.hubs(), 2U);
}

TEST(HubGate, AHubThatEndedIsNotWaitedForAndASilentOneOnlyUntilTheBound) {
  const auto t0 = GateClock::time_point{} + 1h;
  HubGate gate({{"ground", 10, 7410}, {"place-0", 11, 7412}, {"place-1", 12, 7414}}, t0, 20s);
  HubGatePorts ports;
  ports.bound = {{10, {7410}}, {12, {}}};  // place-0 is gone
  EXPECT_EQ(gate.look(t0 + 1s, ports.reader()), HubGate::Verdict::Wait);
  EXPECT_EQ(gate.gone(), std::vector<std::string>{"place-0"});
  // place-1 never listens: just before the bound the gate still waits, at it it gives up.
  EXPECT_EQ(gate.look(t0 + 20s - 1ms, ports.reader()), HubGate::Verdict::Wait);
  EXPECT_EQ(gate.look(t0 + 20s, ports.reader()), HubGate::Verdict::GaveUp);
  ASSERT_EQ(gate.waiting().size(), 1U);
  EXPECT_EQ(gate.waiting().front().name, "place-1");
  // No hub at all (a host with UAVs only): open at once.
  HubGate none({}, t0, 20s);
  EXPECT_EQ(none.look(t0, ports.reader()), HubGate::Verdict::Open);
}

}  // namespace
}  // namespace pheromesh::cli
