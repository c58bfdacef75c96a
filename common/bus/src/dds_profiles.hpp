// The DDS profiles a process can name with --dds-profile, per vendor:
//   "onehost", "onehost-unicast"  built in (deploy/dds/<vendor>-<name>.xml)
//   "netns"                       built in: one network namespace per process
//                                 on a bridge (pheromesh run's network faults)
//   "lan", "lan-unicast"          built in: a swarm over several hosts, with
//                                 multicast discovery or with unicast peers
//                                 (the addresses given as `peers`)
//   "default"                     the vendor's own defaults
//   FILE[,FILE...]                configuration files; each vendor uses the one
//                                 written for it (by its root element), so one
//                                 --dds-profile serves a mixed swarm.
#pragma once
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "pheromesh/bus/qos.hpp"

namespace pheromesh::bus {

// Cyclone configuration XML for a profile; "" means vendor defaults. Throws
// std::runtime_error naming the problem (unreadable file, no Cyclone file).
// `peers`: IPv4 addresses for the lan profiles' unicast discovery (an error
// with any other profile). `swarm_processes`: how many processes of the swarm
// share this host (0: not known); above kQuietHeartbeatAbove the one-host
// profiles ask for acknowledgements every second instead of every 100 ms
// (cyclone_heartbeat).
std::string cyclone_config(const std::string& profile, const std::vector<std::string>& peers = {},
                           uint32_t swarm_processes = 0);

// Cyclone 0.10 sends each heartbeat of a discovery writer to every matched
// participant until all have acknowledged. While more than about 40
// processes discover each other on one 2-core host, heartbeats every 100 ms
// (Cyclone's default) are most of the traffic, the acknowledgements fall
// behind and the heartbeats repeat: measured with 105 Cyclone processes
// (bench/discovery_profile.sh), 100 ms never finished in 150 s (each process
// heard 20-87 of 105, 4 runs), 500 ms took 67 s, 1 s 36-39 s; 60 processes
// took 14-17 s against 4 s, 40 processes 2.0 s against 1.8 s. A small swarm
// keeps 100 ms: with 1 s a 10-UAV lockstep run took 2.5 s longer (its
// discovery and its last acknowledged writes wait for a heartbeat).
inline constexpr uint32_t kQuietHeartbeatAbove = 40;
// The HeartbeatInterval for a one-host swarm of that many processes; empty:
// Cyclone's default (100 ms).
std::string cyclone_heartbeat(uint32_t swarm_processes);

// How a Fast DDS reliable writer asks for acknowledgements. Fast DDS 2.9
// piggybacks a heartbeat that wants an answer on every write, so each 5 Hz
// write of a realtime swarm (a UAV's state, a batch of deposits, a halo)
// brought an ACKNACK back: one datagram and a wake-up each (issue 44,
// docs/benchmarks.md "Where a UAV tick goes"). A swarm of more than
// kQuietHeartbeatAbove processes heartbeats once a second instead, without
// piggybacking, as Cyclone's one-host profiles do (cyclone_heartbeat): a
// reader that missed a sample asks for it within a second. That holds for
// lockstep too: at 100 ms every writer that wrote in a tick still had an
// unacknowledged sample at its next heartbeat, and the heartbeats, their
// ACKNACKs and the timer wake-ups behind both cost a 100-UAV lockstep swarm
// a quarter of its ticks per second (docs/benchmarks.md, "Lockstep
// heartbeats"). A small swarm keeps 100 ms and the piggyback.
struct FastDdsWriterPace {
  std::chrono::milliseconds heartbeat{100};
  bool piggyback = true;
  bool operator==(const FastDdsWriterPace&) const = default;
};
FastDdsWriterPace fastdds_writer_pace(uint32_t swarm_processes);

struct FastDdsProfile {
  std::string xml;   // built-in profiles: the XML text ...
  std::string name;  // ... and the participant profile in it
  std::string file;  // a user's Fast DDS XML file (its default profile is used)
  std::vector<std::string> peers;  // IPv4 addresses: initial peers added to the participant QoS
};
// Throws std::runtime_error naming the problem.
FastDdsProfile fastdds_profile(const std::string& profile, const std::vector<std::string>& peers = {});

}  // namespace pheromesh::bus
