// The DDS profiles a process can name with --dds-profile, per vendor:
//   "onehost", "onehost-unicast"  built in (deploy/dds/<vendor>-<name>.xml)
//   "netns"                       built in: one network namespace per process
//                                 on a bridge (pheromesh run's network faults)
//   "default"                     the vendor's own defaults
//   FILE[,FILE...]                configuration files; each vendor uses the one
//                                 written for it (by its root element), so one
//                                 --dds-profile serves a mixed swarm.
#pragma once
#include <string>

namespace pheromesh::bus {

// Cyclone configuration XML for a profile; "" means vendor defaults. Throws
// std::runtime_error naming the problem (unreadable file, no Cyclone file).
std::string cyclone_config(const std::string& profile);

struct FastDdsProfile {
  std::string xml;   // built-in profiles: the XML text ...
  std::string name;  // ... and the participant profile in it
  std::string file;  // a user's Fast DDS XML file (its default profile is used)
};
// Throws std::runtime_error naming the problem.
FastDdsProfile fastdds_profile(const std::string& profile);

}  // namespace pheromesh::bus
