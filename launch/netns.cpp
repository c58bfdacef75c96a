#include "netns.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <sched.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "child_spawn.hpp"

namespace pheromesh::cli {

namespace fs = std::filesystem;

namespace {

constexpr const char* kNetnsDir = "/run/netns";
// At most this many processes: each namespace holds a permanent neighbour
// entry for every other process (see make_slots), N (N - 1) entries in all,
// 89 700 at 300. (A Linux bridge would take 1024 ports.)
constexpr std::size_t kMaxPorts = 300;
// The processes' interface, the same name in every namespace (the netns DDS
// profiles name it).
constexpr const char* kIface = "phm0";
// The veth MTU, as large as veth takes (loopback has 65536): DDS sends
// datagrams of up to ~15 KB (Cyclone's default MaxMessageSize), which a 1500
// byte MTU would cut into IP fragments; then one lost fragment loses the
// datagram, and a "loss 20%" would lose most large datagrams, not 20 %.
constexpr int kMtu = 65535;

// A fixed, locally administered MAC address per slot ("phm" + the slot).
std::string mac_of(uint32_t slot) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "02:70:68:6d:%02x:%02x", (slot >> 8U) & 0xffU, slot & 0xffU);
  return buf;
}

std::string trim_output(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s.empty() ? "(no message)" : s;
}

std::string describe(const std::vector<std::string>& argv, const ToolResult& r) {
  std::string cmd;
  for (const auto& a : argv) cmd += (cmd.empty() ? "" : " ") + a;
  return "`" + cmd + "` failed (exit " + std::to_string(r.rc) + "): " + trim_output(r.output);
}

// Runs argv; nullopt on success, else the command and its message.
std::optional<std::string> must(const std::vector<std::string>& argv, const std::string& input = "",
                                int netns_fd = -1) {
  const ToolResult r = run_tool(argv, input, netns_fd);
  if (r.rc == 0) return std::nullopt;
  return describe(argv, r) + (input.empty() ? "" : "\n  its input was:\n" + input);
}

int open_netns(const std::string& name) {
  return open((std::string(kNetnsDir) + "/" + name).c_str(), O_RDONLY | O_CLOEXEC);
}

}  // namespace

uint32_t Subnet::hosts() const {
  const uint64_t size = uint64_t{1} << (32 - prefix);
  return static_cast<uint32_t>(size - 2);
}

std::string Subnet::address(uint32_t slot) const {
  in_addr a{};
  a.s_addr = htonl(base + 1 + slot);
  char buf[INET_ADDRSTRLEN] = {};
  inet_ntop(AF_INET, &a, buf, sizeof buf);
  return buf;
}

std::string Subnet::text() const {
  in_addr a{};
  a.s_addr = htonl(base);
  char buf[INET_ADDRSTRLEN] = {};
  inet_ntop(AF_INET, &a, buf, sizeof buf);
  return std::string(buf) + "/" + std::to_string(prefix);
}

core::Result<Subnet> parse_subnet(const std::string& cidr) {
  const auto slash = cidr.find('/');
  const auto bad = [&](const std::string& why) {
    return core::Error{"--netns-subnet '" + cidr + "': " + why + " (expected an IPv4 subnet such as 10.77.0.0/16)"};
  };
  if (slash == std::string::npos) return bad("no prefix length");
  in_addr a{};
  if (inet_pton(AF_INET, cidr.substr(0, slash).c_str(), &a) != 1) return bad("not an IPv4 address");
  const std::string len = cidr.substr(slash + 1);
  if (len.empty() || len.size() > 2 || len.find_first_not_of("0123456789") != std::string::npos)
    return bad("bad prefix length");
  const int prefix = std::stoi(len);
  if (prefix < 8 || prefix > 28) return bad("the prefix length must be between 8 and 28");
  Subnet s;
  s.prefix = prefix;
  const uint32_t mask = prefix == 0 ? 0 : ~uint32_t{0} << (32 - prefix);
  s.base = ntohl(a.s_addr) & mask;
  if (s.base != ntohl(a.s_addr)) return bad("host bits are set; the network address is " + s.text());
  return s;
}

ToolResult run_tool(const std::vector<std::string>& argv, const std::string& input, int netns_fd) {
  ToolResult r;
  // stdin from a socket (send with MSG_NOSIGNAL: a tool that exits early
  // must not SIGPIPE the launcher); stdout and stderr into a temporary file,
  // read once the tool has exited (no pipe to fill up).
  int in[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, in) != 0) {
    r.output = std::string("socketpair: ") + std::strerror(errno);
    return r;
  }
  std::FILE* out = std::tmpfile();
  if (out == nullptr) {
    close(in[0]);
    close(in[1]);
    r.output = std::string("tmpfile: ") + std::strerror(errno);
    return r;
  }
  const int out_fd = fileno(out);
  std::vector<std::string> copy = argv;
  std::vector<char*> args;
  for (auto& a : copy) args.push_back(a.data());
  args.push_back(nullptr);
  std::optional<StopSignalsHeld> held(std::in_place);  // a stop sent while it forks is the helper's, not lost
  const pid_t pid = fork();
  if (pid == 0) {
    held->release_in_child();
    if (netns_fd >= 0 && setns(netns_fd, CLONE_NEWNET) != 0) {
      dprintf(out_fd, "setns: %s\n", std::strerror(errno));
      _exit(126);
    }
    dup2(in[1], STDIN_FILENO);
    dup2(out_fd, STDOUT_FILENO);
    dup2(out_fd, STDERR_FILENO);
    execvp(args[0], args.data());
    dprintf(STDERR_FILENO, "cannot run %s: %s\n", args[0], std::strerror(errno));
    _exit(127);
  }
  held.reset();
  close(in[1]);
  if (pid < 0) {
    close(in[0]);
    std::fclose(out);
    r.output = std::string("fork: ") + std::strerror(errno);
    return r;
  }
  std::size_t sent = 0;
  while (sent < input.size()) {
    const ssize_t n = send(in[0], input.data() + sent, input.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    sent += static_cast<std::size_t>(n);
  }
  close(in[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  r.rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  std::rewind(out);
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, out)) > 0 && r.output.size() < 65536) r.output.append(buf, n);
  std::fclose(out);
  return r;
}

std::vector<std::string> remove_stale_namespaces() {
  std::vector<std::string> stale;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(kNetnsDir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("phm-", 0) != 0) continue;
    const auto dash = name.find('-', 4);
    if (dash == std::string::npos) continue;
    const std::string pid = name.substr(4, dash - 4);
    if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos) continue;
    // A launcher that still runs keeps its namespaces (a recycled pid only
    // delays the clean-up of a dead one's).
    std::error_code exists_ec;
    if (fs::exists("/proc/" + pid, exists_ec)) continue;
    stale.push_back(name);
  }
  if (stale.empty()) return stale;
  std::string batch;
  for (const auto& n : stale) batch += "netns del " + n + "\n";
  if (auto err = must({"ip", "-force", "-batch", "-"}, batch)) spdlog::warn("removing stale namespaces: {}", *err);
  return stale;
}

std::optional<std::string> NetnsSwarm::create(const std::vector<std::string>& names) {
  if (geteuid() != 0) {
    return "network faults (partition, loss) run every process in its own network namespace, which needs root "
           "(CAP_NET_ADMIN and CAP_SYS_ADMIN); run `pheromesh run` as root (e.g. with sudo), or leave out the "
           "partition and loss events";
  }
  if (run_tool({"ip", "-V"}).rc != 0) {
    return "network faults need the `ip` program (iproute2), which cannot be run; install it (apt-get install "
           "iproute2)";
  }
  if (run_tool({"nft", "--version"}).rc != 0) {
    return "network faults need the `nft` program (nftables), which cannot be run; install it (apt-get install "
           "nftables)";
  }
  if (names.size() > kMaxPorts) {
    return "network faults: " + std::to_string(names.size()) + " processes are more than the " +
           std::to_string(kMaxPorts) +
           " that network namespaces are made for (each one holds a fixed neighbour entry per other process: N^2 "
           "entries); leave out the partition and loss events, or run fewer processes";
  }
  if (names.size() > subnet_.hosts()) {
    return "network faults: the subnet " + subnet_.text() + " has " + std::to_string(subnet_.hosts()) +
           " addresses, too few for " + std::to_string(names.size()) +
           " processes; give a larger one with --netns-subnet";
  }
  auto fail = [this](const std::string& what) {
    teardown();
    return what;
  };
  if (auto err = must({"ip", "netns", "add", switch_ns()})) {
    return fail("cannot create a network namespace: " + *err +
                "\n  (network namespaces need root with CAP_SYS_ADMIN and a writable /run/netns; in a container, "
                "run it privileged)");
  }
  switch_made_ = true;
  switch_fd_ = open_netns(switch_ns());
  if (switch_fd_ < 0)
    return fail("cannot open " + std::string(kNetnsDir) + "/" + switch_ns() + ": " + std::strerror(errno));
  // The bridge; multicast snooping off, so that every port gets every
  // multicast frame (DDS discovery) without waiting for IGMP reports.
  if (auto err = must({"ip", "-n", switch_ns(), "-batch", "-"},
                      "link add br0 type bridge mcast_snooping 0\nlink set br0 up\n")) {
    return fail("cannot create the bridge: " + *err + "\n  (the kernel needs bridge and veth support)");
  }
  // Partition and loss rules filter bridged frames: check nft can.
  if (auto err = nft_in_switch("add table bridge phm_probe\n"
                               "add chain bridge phm_probe forward { type filter hook forward priority 0 ; }\n"
                               "add rule bridge phm_probe forward meta l4proto udp numgen random mod 100 < 1 drop\n"
                               "delete table bridge phm_probe\n")) {
    return fail("nftables cannot filter bridged traffic here: " + *err +
                "\n  (the kernel needs nf_tables with the bridge family and numgen)");
  }
  if (auto err = make_slots(names)) return fail(*err);
  return std::nullopt;
}

std::optional<std::string> NetnsSwarm::add(const std::string& name) {
  if (slots_.count(name) != 0) return std::nullopt;
  if (slots_.size() + 1 > std::min<std::size_t>(kMaxPorts, subnet_.hosts())) {
    return "no room for one more process in the namespaces (subnet " + subnet_.text() + ")";
  }
  return make_slots({name});
}

std::optional<std::string> NetnsSwarm::make_slots(const std::vector<std::string>& names) {
  std::vector<std::string> fresh;
  std::string add_ns, add_ports;
  for (const auto& name : names) {
    if (slots_.count(name) != 0) continue;
    Slot s;
    s.index = static_cast<uint32_t>(slots_.size());
    s.netns = prefix_ + "-" + std::to_string(s.index);
    s.port = "v" + std::to_string(s.index);
    add_ns += "netns add " + s.netns + "\n";
    add_ports += "link add " + s.port + " mtu " + std::to_string(kMtu) + " type veth peer name " + kIface + " mtu " +
                 std::to_string(kMtu) + " address " + mac_of(s.index) + " netns " + s.netns + "\n";
    add_ports += "link set " + s.port + " master br0 up\n";
    slots_[name] = s;
    fresh.push_back(name);
  }
  if (fresh.empty()) return std::nullopt;
  // Batches: one `ip` run costs a few ms, a run per command ~5 per process.
  if (auto err = must({"ip", "-batch", "-"}, add_ns)) return "cannot create the processes' namespaces: " + *err;
  for (const auto& name : fresh) {
    slots_[name].fd = open_netns(slots_[name].netns);
    if (slots_[name].fd < 0) return "cannot open the namespace of " + name + ": " + std::strerror(errno);
  }
  if (auto err = must({"ip", "-n", switch_ns(), "-batch", "-"}, add_ports))
    return "cannot create the veth pairs: " + *err;
  // Every namespace knows every other process's MAC address for good:
  // Linux keeps one ARP table for all namespaces, and its default limit
  // (net.ipv4.neigh.default.gc_thresh3 = 1024 entries) is reached with ~33
  // processes that all talk to each other (N (N - 1) entries). Past it,
  // sends fail (ENOBUFS, counted as UdpSndbufErrors), the host's own ARP
  // suffers too, and DDS discovery stalled for 30-60 s (measured with 42
  // processes). Permanent entries do not count against the limit, and no
  // ARP request is flooded to every port either.
  auto neigh_of = [this](const Slot& peer) {
    return "neigh add " + subnet_.address(peer.index) + " lladdr " + mac_of(peer.index) + " dev " + kIface +
           " nud permanent\n";
  };
  for (const auto& name : fresh) {
    const Slot& s = slots_[name];
    std::string cfg = "link set lo up\naddr add " + subnet_.address(s.index) + "/" + std::to_string(subnet_.prefix) +
                      " dev " + kIface + "\nlink set " + kIface + " up\nroute add 224.0.0.0/4 dev " + kIface + "\n";
    for (const auto& [other, peer] : slots_) {
      if (other != name) cfg += neigh_of(peer);
    }
    if (auto err = must({"ip", "-n", s.netns, "-batch", "-"}, cfg))
      return "cannot configure the namespace of " + name + ": " + *err;
  }
  // The namespaces made before learn the new ones.
  for (const auto& [other, peer] : slots_) {
    if (std::find(fresh.begin(), fresh.end(), other) != fresh.end()) continue;
    std::string cfg;
    for (const auto& name : fresh) cfg += neigh_of(slots_[name]);
    if (auto err = must({"ip", "-n", peer.netns, "-batch", "-"}, cfg))
      return "cannot configure the namespace of " + other + ": " + *err;
  }
  return std::nullopt;
}

int NetnsSwarm::fd_of(const std::string& name) const {
  const auto it = slots_.find(name);
  return it == slots_.end() ? -1 : it->second.fd;
}

std::string NetnsSwarm::namespace_of(const std::string& name) const {
  const auto it = slots_.find(name);
  return it == slots_.end() ? "" : it->second.netns;
}

std::string NetnsSwarm::address_of(const std::string& name) const {
  const auto it = slots_.find(name);
  return it == slots_.end() ? "" : subnet_.address(it->second.index);
}

std::optional<std::string> NetnsSwarm::nft_in_switch(const std::string& script) const {
  return must({"nft", "-f", "-"}, script, switch_fd_);
}

std::optional<std::string> NetnsSwarm::ports_of(const std::vector<std::string>& names, std::string& set) const {
  set.clear();
  for (const auto& n : names) {
    const auto it = slots_.find(n);
    if (it == slots_.end()) return n + " has no network namespace";
    set += (set.empty() ? "\"" : ", \"") + it->second.port + "\"";
  }
  return std::nullopt;
}

std::optional<std::string> NetnsSwarm::cut_off(int id, const std::vector<std::string>& names) {
  std::string ports;
  if (auto err = ports_of(names, ports)) return err;
  if (ports.empty()) return "a partition needs at least one process";
  const std::string table = "phm_cut_" + std::to_string(id);
  // Frames between a port inside and a port outside are dropped, both ways
  // (ARP too); frames among the inside ports, and among the outside ones,
  // pass. A flooded multicast frame is filtered per receiving port.
  std::ostringstream s;
  s << "table bridge " << table << " {\n"
    << "  counter dropped { }\n"
    << "  set inside { type ifname; elements = { " << ports << " } }\n"
    << "  chain forward {\n"
    << "    type filter hook forward priority 0; policy accept;\n"
    << "    iifname @inside oifname != @inside counter name dropped drop\n"
    << "    iifname != @inside oifname @inside counter name dropped drop\n"
    << "  }\n"
    << "}\n";
  if (auto err = nft_in_switch(s.str())) return err;
  tables_[id] = table;
  return std::nullopt;
}

std::optional<std::string> NetnsSwarm::drop_share(int id, double share, const std::vector<std::string>& names) {
  std::string ports;
  if (auto err = ports_of(names, ports)) return err;
  const std::string table = "phm_loss_" + std::to_string(id);
  // Each frame forwarded to a receiving port is dropped with probability
  // `share`, independently (a flooded multicast frame per receiver). Only
  // IPv4: dropping ARP would add losses of its own.
  const auto per10k = static_cast<long>(std::lround(share * 10000.0));
  const std::string draw = per10k >= 10000 ? "" : "numgen random mod 10000 < " + std::to_string(per10k) + " ";
  const std::string match = (ports.empty() ? "" : "oifname @lossy ") + std::string("ether type ip ");
  // Two counters: the frames the rule saw and those it dropped, so that the
  // share really dropped can be reported.
  std::ostringstream s;
  s << "table bridge " << table << " {\n"
    << "  counter seen { }\n"
    << "  counter dropped { }\n";
  if (!ports.empty()) s << "  set lossy { type ifname; elements = { " << ports << " } }\n";
  s << "  chain forward {\n"
    << "    type filter hook forward priority 0; policy accept;\n"
    << "    " << match << "counter name seen\n"
    << "    " << match << draw << "counter name dropped drop\n"
    << "  }\n"
    << "}\n";
  if (auto err = nft_in_switch(s.str())) return err;
  tables_[id] = table;
  return std::nullopt;
}

std::optional<std::string> NetnsSwarm::remove_rules(int id, RuleCounts* counts) {
  const auto it = tables_.find(id);
  if (it == tables_.end()) return std::nullopt;
  const std::string table = it->second;
  tables_.erase(it);
  if (counts != nullptr) {
    // {"nftables": [{"metainfo": ...}, {"counter": {"name": "seen", "packets": N, ...}}, ...]}
    const ToolResult r = run_tool({"nft", "-j", "list", "table", "bridge", table}, "", switch_fd_);
    try {
      const auto j = nlohmann::json::parse(r.output);
      for (const auto& item : j.at("nftables")) {
        if (!item.contains("counter")) continue;
        const auto& c = item["counter"];
        const auto packets = c.at("packets").get<uint64_t>();
        if (c.at("name") == "seen") counts->seen = packets;
        if (c.at("name") == "dropped") counts->dropped = packets;
      }
    } catch (const std::exception& e) {
      spdlog::warn("cannot read the counters of nft table {}: {} ({})", table, e.what(), trim_output(r.output));
    }
  }
  return nft_in_switch("delete table bridge " + table + "\n");
}

std::optional<UdpCounters> NetnsSwarm::udp_counters() const {
  // Each namespace counts its own datagrams from zero: enter each one, read
  // /proc/self/net/snmp (the namespace of the reading thread), come back.
  const int self = open("/proc/self/ns/net", O_RDONLY | O_CLOEXEC);
  if (self < 0) return std::nullopt;
  UdpCounters sum;
  bool ok = true;
  for (const auto& [name, s] : slots_) {
    if (s.fd < 0 || setns(s.fd, CLONE_NEWNET) != 0) {
      ok = false;
      break;
    }
    const auto c = read_udp_counters();
    if (!c) ok = false;
    if (c) {
      sum.in_datagrams += c->in_datagrams;
      sum.out_datagrams += c->out_datagrams;
    }
  }
  if (setns(self, CLONE_NEWNET) != 0) {
    // The launcher would now run in a swarm's namespace: do not go on.
    spdlog::critical("cannot return to the launcher's network namespace: {}", std::strerror(errno));
    std::abort();
  }
  close(self);
  if (!ok) return std::nullopt;
  return sum;
}

void NetnsSwarm::teardown() {
  std::string batch;
  for (auto& [name, s] : slots_) {
    if (s.fd >= 0) close(s.fd);
    s.fd = -1;
    batch += "netns del " + s.netns + "\n";
  }
  if (switch_fd_ >= 0) close(switch_fd_);
  switch_fd_ = -1;
  if (switch_made_) batch += "netns del " + switch_ns() + "\n";
  slots_.clear();
  tables_.clear();
  switch_made_ = false;
  if (batch.empty()) return;
  // -force: go on past a namespace that is already gone.
  if (auto err = must({"ip", "-force", "-batch", "-"}, batch)) {
    spdlog::error(
        "removing the network namespaces: {}\n  remove what is left by hand: ip netns list | grep '^{}-' | "
        "xargs -r -n1 ip netns del",
        *err, prefix_);
  }
}

}  // namespace pheromesh::cli
