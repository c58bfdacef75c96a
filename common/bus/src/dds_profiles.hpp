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
#include <string>
#include <vector>

namespace pheromesh::bus {

// Cyclone configuration XML for a profile; "" means vendor defaults. Throws
// std::runtime_error naming the problem (unreadable file, no Cyclone file).
// `peers`: IPv4 addresses for the lan profiles' unicast discovery (an error
// with any other profile).
std::string cyclone_config(const std::string& profile, const std::vector<std::string>& peers = {});

struct FastDdsProfile {
  std::string xml;   // built-in profiles: the XML text ...
  std::string name;  // ... and the participant profile in it
  std::string file;  // a user's Fast DDS XML file (its default profile is used)
  std::vector<std::string> peers;  // IPv4 addresses: initial peers added to the participant QoS
};
// Throws std::runtime_error naming the problem.
FastDdsProfile fastdds_profile(const std::string& profile, const std::vector<std::string>& peers = {});

}  // namespace pheromesh::bus
