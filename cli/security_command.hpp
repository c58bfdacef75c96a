// `pheromesh security init DIR`: the CA, one identity per process of a swarm,
// the governance and each identity's signed permissions (docs/security.md).
#pragma once

#include <cstdint>
#include <string>

namespace pheromesh::cli {

struct SecurityInitOptions {
  std::string dir;
  std::string scenario;  // the swarm's size and regions (optional with --uavs and --regions)
  uint32_t uavs = 0;     // 0: the scenario's
  uint32_t regions = 0;  // 0: the scenario's
  bool standby = false;  // a standby identity per place agent (also the scenario's run.standby)
  uint32_t probes = 0;   // probe-N identities for tests and benches
  std::string protection = "encrypt";
  uint32_t days = 365;
  bool force = false;
};

int run_security_init(const SecurityInitOptions& o);

inline constexpr const char* kSecurityFooter =
    "\nWhat it makes (DIR, mode 0700):\n"
    "  ca.pem ca.key               the swarm's CA (ECDSA P-256). ca.key signs everything below: keep it\n"
    "                              off the swarm's hosts once the identities are made (docs/security.md)\n"
    "  governance.xml/.p7s         domain rules: nobody unauthenticated joins; every topic is read- and\n"
    "                              write-access controlled; --protection encrypt (AES-GCM), sign (GMAC)\n"
    "                              or none (authenticated and access-controlled, traffic in clear)\n"
    "  <name>/cert.pem key.pem     one identity per process: uav-N, place-R, place-R.r1 (--standby),\n"
    "                              ground, monitor (read-only: pheromesh attach); key.pem is 0600\n"
    "  <name>/permissions.xml/.p7s what the process may publish and subscribe, topic by topic and\n"
    "                              partition by partition (a UAV: its state and deposits to its home\n"
    "                              place agent, detections, broadcasts; only the ground station the\n"
    "                              clock and commands)\n"
    "\nExamples:\n"
    "  pheromesh security init out/sec --scenario small-test\n"
    "  pheromesh run small-test --secure out/sec --ticks 100\n"
    "  pheromesh attach --domain 0 --secure out/sec\n"
    "  pheromesh security init out/sec --scenario shao2020-50x50 --uavs 40 --standby --protection sign --force\n";

}  // namespace pheromesh::cli
