// Network faults for `pheromesh run` (docs/faults.md): every process of the
// swarm in its own network namespace, all of them plugged into one bridge, so
// that nft rules can cut some of them off (partition) or drop a share of what
// they receive (loss) without touching the host's own network.
//
//   phm-<launcher pid>-sw     the "switch": a namespace holding only the bridge
//                             br0 and the switch ends v<slot> of the veth pairs
//   phm-<launcher pid>-<slot> one per process: lo, and phm0 (the other veth end)
//                             with the slot's address in the subnet, a route
//                             for multicast (DDS discovery) on phm0
//
// The bridge lives in its own namespace, not in the launcher's: nothing of
// the swarm's network appears among the host's interfaces, routes or
// firewall (the host's br_netfilter / iptables FORWARD rules never see the
// swarm's frames), two runs at once cannot clash even with the same subnet,
// and deleting the namespaces deletes every veth and the bridge with them.
//
// Partition and loss are nft rules of the bridge family in the switch
// namespace, one table per fault event, on the frames the bridge forwards
// from one process's port to another's. There a multicast announcement
// flooded by the bridge is filtered per receiving port, so a partition is
// exact both ways and the processes inside it keep discovering each other;
// and one rule covers any number of processes.
//
// The `ip` and `nft` programs do the work (their exit codes are checked and
// their messages reported); this needs root (CAP_NET_ADMIN and CAP_SYS_ADMIN).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/result.hpp"
#include "proc_stats.hpp"

namespace pheromesh::cli {

// An IPv4 subnet for the processes' addresses, e.g. 10.77.0.0/16.
struct Subnet {
  uint32_t base = 0;  // network address, host byte order
  int prefix = 16;
  [[nodiscard]] uint32_t hosts() const;                    // usable addresses: network and broadcast excluded
  [[nodiscard]] std::string address(uint32_t slot) const;  // slot 0 -> base + 1
  [[nodiscard]] std::string text() const;                  // "10.77.0.0/16"
};
// Accepts A.B.C.D/L with 8 <= L <= 28; errors name the option.
core::Result<Subnet> parse_subnet(const std::string& cidr);

// Runs a program (argv[0] looked up in PATH) with `input` on its stdin, inside
// the network namespace `netns_fd` if >= 0. Returns its exit code (127: could
// not run) and what it printed (stdout and stderr).
struct ToolResult {
  int rc = -1;
  std::string output;
};
ToolResult run_tool(const std::vector<std::string>& argv, const std::string& input = "", int netns_fd = -1);

// Removes the namespaces `pheromesh run` left behind when it was killed
// (phm-<pid>-* whose launcher pid no longer exists). Returns their names.
std::vector<std::string> remove_stale_namespaces();

class NetnsSwarm {
 public:
  NetnsSwarm(std::string prefix, Subnet subnet) : prefix_(std::move(prefix)), subnet_(subnet) {}
  ~NetnsSwarm() { teardown(); }
  NetnsSwarm(const NetnsSwarm&) = delete;
  NetnsSwarm& operator=(const NetnsSwarm&) = delete;

  // Checks that this can work (root, ip, nft with the bridge family), makes
  // the switch and one namespace per name. On error everything made is
  // removed and the message says why and what to do.
  std::optional<std::string> create(const std::vector<std::string>& names);
  // One more process (e.g. a standby started later); no-op if it has one.
  std::optional<std::string> add(const std::string& name);

  // The namespace of a process as an open fd for setns(2) (-1: none), its
  // name and its address.
  [[nodiscard]] int fd_of(const std::string& name) const;
  [[nodiscard]] std::string namespace_of(const std::string& name) const;
  [[nodiscard]] std::string address_of(const std::string& name) const;
  [[nodiscard]] const std::string& prefix() const { return prefix_; }
  [[nodiscard]] std::size_t size() const { return slots_.size(); }

  // Fault `id`: the processes `names` can reach one another and nobody else.
  std::optional<std::string> cut_off(int id, const std::vector<std::string>& names);
  // Fault `id`: drop `share` (0..1) of the IPv4 packets each of `names`
  // receives from other processes (every process if `names` is empty).
  std::optional<std::string> drop_share(int id, double share, const std::vector<std::string>& names);
  // Removes fault `id`'s rules; `counts` (if given) gets what they did.
  struct RuleCounts {
    std::optional<uint64_t> seen;     // loss: IPv4 frames to the lossy ports
    std::optional<uint64_t> dropped;  // frames the rules dropped
  };
  std::optional<std::string> remove_rules(int id, RuleCounts* counts = nullptr);

  // UDP datagrams over every namespace (each process's own counters).
  [[nodiscard]] std::optional<UdpCounters> udp_counters() const;

  // Deletes every namespace made (which deletes the bridge and the veth
  // pairs). Idempotent.
  void teardown();

 private:
  struct Slot {
    uint32_t index = 0;
    std::string netns;  // phm-<pid>-<index>
    std::string port;   // the switch end: v<index>
    int fd = -1;
  };
  [[nodiscard]] std::string switch_ns() const { return prefix_ + "-sw"; }
  std::optional<std::string> make_slots(const std::vector<std::string>& names);
  std::optional<std::string> nft_in_switch(const std::string& script) const;
  std::optional<std::string> ports_of(const std::vector<std::string>& names, std::string& set) const;

  std::string prefix_;
  Subnet subnet_;
  int switch_fd_ = -1;
  bool switch_made_ = false;
  std::map<std::string, Slot> slots_;  // by process name
  std::map<int, std::string> tables_;  // fault id -> nft table in the switch
};

}  // namespace pheromesh::cli
