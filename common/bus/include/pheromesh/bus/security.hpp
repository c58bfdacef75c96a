// DDS Security for a pheromesh swarm, vendor-neutral: which identity each
// process has, what each role may publish and subscribe (topics and
// partitions, from the routing in bus.hpp), the governance and permissions
// documents (OMG DDS Security 1.1, the XML both vendors' builtin
// Access-Permissions plugins read), and where `pheromesh security init`
// puts the files. The certificates and S/MIME signatures are made by
// pheromesh::auth (OpenSSL); the vendors' buses hand these files to their
// builtin PKI-DH, Access-Permissions and AES-GCM-GMAC plugins.
//
// A directory made by `pheromesh security init DIR`:
//   DIR/ca.pem, DIR/ca.key           the swarm's CA (identity and permissions CA)
//   DIR/governance.xml, .p7s         the domain rules, signed by the CA
//   DIR/identities.txt               the identities made, one name per line
//   DIR/<name>/cert.pem, key.pem     one identity per process (key.pem 0600)
//   DIR/<name>/permissions.xml, .p7s its grant, signed by the CA
// <name> is the process name: uav-N, place-R, place-R.rK (standby K), ground,
// monitor (pheromesh attach, pheromesh-ground --attach: read-only), and
// probe-N for tests and benches when asked for.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/result.hpp"

namespace pheromesh::bus {

// How the governance protects what the swarm sends once authenticated and
// admitted. Authentication and access control are on in all three.
enum class Protection : uint8_t {
  Encrypt,  // discovery, liveliness, submessages and payloads AES-GCM encrypted
  Sign,     // the same, authenticated (GMAC) but readable on the wire
  None,     // no cryptographic protection of the traffic (still authenticated, access-controlled)
};
const char* to_string(Protection p);
core::Result<Protection> parse_protection(const std::string& s);

// What one grant allows: a topic (DDS name) in one of some partitions
// (DDS fnmatch patterns).
struct TopicRule {
  std::string topic;
  std::vector<std::string> partitions;
};

struct Grant {
  std::string name;     // the identity: the process name
  std::string subject;  // the certificate's subject, e.g. "CN=uav-3"
  std::vector<TopicRule> publish;
  std::vector<TopicRule> subscribe;
};

// The identity name of the read-only monitor (pheromesh attach).
inline constexpr const char* kMonitorIdentity = "monitor";

// The processes of a swarm that `security init` makes identities for.
struct SwarmShape {
  uint32_t uavs = 0;
  uint32_t regions = 0;
  uint32_t standby = 0;  // standby replicas per place agent (0 or 1 today)
  // Identities probe-0 .. probe-(N-1) for pheromesh-test-probe and the
  // benches: they read everything and publish only health records and
  // deposits.
  uint32_t probes = 0;
};

// The certificate subject of identity `name`.
std::string subject_of(const std::string& name);
// The grants of every process of `shape`: UAVs, place agents (and their
// standbys), the ground station, the monitor and the probes.
std::vector<Grant> swarm_grants(const SwarmShape& shape);
// The grant of one process by its name; an error for a name that is no role.
core::Result<Grant> grant_for(const std::string& name, const SwarmShape& shape);

// The documents, not yet signed. Dates as "YYYY-MM-DDThh:mm:ss" (UTC).
std::string governance_xml(Protection p);
std::string permissions_xml(const Grant& g, const std::string& not_before, const std::string& not_after);

// The files one process needs.
struct SecurityFiles {
  std::string ca;           // identity CA and permissions CA (PEM)
  std::string governance;   // signed (S/MIME)
  std::string cert;         // this identity's certificate (PEM)
  std::string key;          // its private key (PEM, 0600)
  std::string permissions;  // signed (S/MIME)
};
SecurityFiles security_files(const std::string& dir, const std::string& identity);
// The same, checked: an error naming the first missing file and the command
// that makes it.
core::Result<SecurityFiles> find_security_files(const std::string& dir, const std::string& identity);

// DDS Security over Fast DDS 2.9.1 (Debian's) needs discovery on one socket:
// with multicast discovery (the flat profiles onehost, netns and lan) a
// participant takes discovery from its multicast and its unicast socket in
// two threads, and their secure handling of a new participant races
// (eProsima/Fast-DDS#4188, fixed in 2.10): measured, 20 secure probes
// started together found every peer in 1, 8 and 7 of 20 under onehost and
// in 20 of 20 three times under onehost-unicast, and two probes of 100
// died (an assertion in SecurityManager::discovered_participant, a
// segmentation fault in PDPSimple::assignRemoteEndpoints; docs/security.md).
// The error for `--secure` over `vendor` with `profile` (a process in cells
// has one unicast discovery socket: `cell`), or nothing.
std::optional<std::string> check_secure_profile(const std::string& vendor, const std::string& profile, bool cell);

}  // namespace pheromesh::bus
