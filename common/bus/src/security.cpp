#include "pheromesh/bus/security.hpp"

#include <filesystem>

#include "pheromesh/bus/qos.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/bus/routing.hpp"

namespace pheromesh::bus {
namespace {

using namespace routing;  // NOLINT: partition names

std::string topic(TopicKind k) { return topic_name(k); }

// Every topic, in every partition: what the ground station and the monitor
// read.
std::vector<TopicRule> read_everything() {
  std::vector<TopicRule> rules;
  for (TopicKind k : kAllTopicKinds) {
    if (k == TopicKind::UavHome) continue;  // the same DDS topic as UavState
    rules.push_back({topic(k), {"*"}});
  }
  return rules;
}

// A process name "uav-N", "place-R", "place-R.rK": the number(s) in it.
bool parse_index(const std::string& s, uint32_t& out) {
  if (s.empty() || s.size() > 9) return false;
  uint32_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + static_cast<uint32_t>(c - '0');
  }
  out = v;
  return true;
}

Grant uav_grant(uint32_t uav, uint32_t regions) {
  const core::RegionId home = core::home_region(uav, regions);
  const core::RegionId backup = core::backup_region(uav, regions);
  Grant g{"uav-" + std::to_string(uav), "", {}, {}};
  // It talks to its gateways only, its home place agent or its backup while
  // its home is dead (docs/architecture.md, "Relays"): its state (with its deposits),
  // detections, broadcasts and lockstep reports go up to them; it hears the
  // lockstep clock, the swarm's broadcasts and the ground station's commands
  // as they relay them.
  std::vector<std::string> states, detections, broadcasts_up, reports, clocks, broadcasts_down, commands;
  for (core::RegionId r : {home, backup}) {
    if (r == backup && backup == home) break;
    states.push_back(home_partition(r));
    detections.push_back(detection_uplink_partition(r));
    broadcasts_up.push_back(broadcast_uplink_partition(r));
    reports.push_back(uav_report_partition(r));
    clocks.push_back(r == home ? uav_clock_partition(r) : uav_backup_clock_partition(r));
    broadcasts_down.push_back(broadcast_downlink_partition(r));
    commands.push_back(command_downlink_partition(r));
  }
  g.publish = {{topic(TopicKind::UavState), states},
               {topic(TopicKind::Detection), detections},
               {topic(TopicKind::Broadcast), broadcasts_up},
               {topic(TopicKind::PhaseDone), reports}};
  g.subscribe = {{topic(TopicKind::View), {view_partition(uav)}},
                 {topic(TopicKind::Broadcast), broadcasts_down},
                 {topic(TopicKind::RelayedClock), clocks},
                 {topic(TopicKind::Command), commands}};
  return g;
}

Grant place_grant(const std::string& name, core::RegionId region) {
  Grant g{name, "", {}, {}};
  // Tiles (TileState: no swarm process writes them today, the place agents
  // own them), its region's field (to the ground station), the UAVs it
  // serves and the tiles other homes' views need (to the place agents), its
  // halo ring, views to its home UAVs,
  // deposits forwarded to the other regions' owners, health, target events,
  // the run's scenario, lockstep reports (its own and its UAVs', relayed),
  // the lockstep clock relayed to its UAVs; the relays of its UAVs' states,
  // detections and broadcasts up, and of the swarm's broadcasts and the
  // ground station's commands down to its UAVs.
  g.publish = {{topic(TopicKind::Tile), {"t.*"}},
               {topic(TopicKind::Field), {kFieldPartition}},
               {topic(TopicKind::PlaceField), {kServedPartition, kAllTilesFor}},
               {topic(TopicKind::Halo), {"h." + std::to_string(region) + ".*"}},
               {topic(TopicKind::View), {"u.*"}},
               {topic(TopicKind::Deposit), {"r.*"}},
               {topic(TopicKind::Health), {kGroundPartition}},
               {topic(TopicKind::TargetEvent), {kGroundPartition}},
               {topic(TopicKind::Scenario), {kGroundPartition}},
               {topic(TopicKind::PhaseDone), {kClockPartition}},
               {topic(TopicKind::RelayedClock), {uav_clock_partition(region), uav_backup_clock_partition(region)}},
               {topic(TopicKind::GroundState), {kGroundPartition}},
               {topic(TopicKind::Detection), {kGroundPartition}},
               {topic(TopicKind::Broadcast), {kBroadcastPartition, broadcast_downlink_partition(region)}},
               {topic(TopicKind::Command), {command_downlink_partition(region)}}};
  g.subscribe = {{topic(TopicKind::Deposit), {region_partition(region)}},
                 {topic(TopicKind::UavState), {home_partition(region)}},
                 {topic(TopicKind::PlaceField), {kServedPartition, tiles_for_partition(region)}},
                 {topic(TopicKind::Halo), {"h.*." + std::to_string(region)}},
                 {topic(TopicKind::Clock), {kClockPartition}},
                 {topic(TopicKind::PhaseDone), {uav_report_partition(region)}},
                 {topic(TopicKind::Command), {kCommandPartition}},
                 {topic(TopicKind::Detection), {detection_uplink_partition(region)}},
                 {topic(TopicKind::Broadcast), {broadcast_uplink_partition(region), kBroadcastPartition}}};
  return g;
}

Grant ground_grant() {
  Grant g{"ground", "", {}, read_everything()};
  // The lockstep clock and the console's (HMAC-signed) commands.
  g.publish = {{topic(TopicKind::Clock), {kClockPartition}}, {topic(TopicKind::Command), {kCommandPartition}}};
  return g;
}

Grant monitor_grant() { return {kMonitorIdentity, "", {}, read_everything()}; }

Grant probe_grant(uint32_t n) {
  // Health records (discovery probes) and deposits (the latency bench's
  // client, the hostile probe): test tools, never a swarm process.
  return {"probe-" + std::to_string(n), "",
          {{topic(TopicKind::Health), {kGroundPartition}}, {topic(TopicKind::Deposit), {"r.*"}}},
          read_everything()};
}

void xml_escape_into(std::string& out, const std::string& s) {
  for (char c : s) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
}

void rules_into(std::string& out, const char* element, const std::vector<TopicRule>& rules) {
  for (const auto& r : rules) {
    out += "        <";
    out += element;
    out += ">\n          <topics><topic>";
    xml_escape_into(out, r.topic);
    out += "</topic></topics>\n          <partitions>";
    for (const auto& p : r.partitions) {
      out += "<partition>";
      xml_escape_into(out, p);
      out += "</partition>";
    }
    out += "</partitions>\n        </";
    out += element;
    out += ">\n";
  }
}

// Every domain a secure swarm can use: Cyclone's parser refuses ids above 230
// in these documents (access_control_parser.c, 0.10.2), two fewer than the
// 232 the port mapping allows.
constexpr const char* kDomains = "<domains><id_range><min>0</min><max>230</max></id_range></domains>";

}  // namespace

const char* to_string(Protection p) {
  switch (p) {
    case Protection::Encrypt: return "encrypt";
    case Protection::Sign: return "sign";
    case Protection::None: return "none";
  }
  return "?";
}

core::Result<Protection> parse_protection(const std::string& s) {
  if (s == "encrypt") return Protection::Encrypt;
  if (s == "sign") return Protection::Sign;
  if (s == "none") return Protection::None;
  return core::Error{"unknown protection '" + s + "' (encrypt, sign or none)"};
}

std::string subject_of(const std::string& name) { return "CN=" + name; }

std::vector<Grant> swarm_grants(const SwarmShape& shape) {
  std::vector<Grant> out;
  for (uint32_t r = 0; r < shape.regions; ++r) {
    out.push_back(place_grant("place-" + std::to_string(r), r));
    for (uint32_t k = 1; k <= shape.standby; ++k) {
      out.push_back(place_grant("place-" + std::to_string(r) + ".r" + std::to_string(k), r));
    }
  }
  for (uint32_t u = 0; u < shape.uavs; ++u) out.push_back(uav_grant(u, shape.regions));
  out.push_back(ground_grant());
  out.push_back(monitor_grant());
  for (uint32_t p = 0; p < shape.probes; ++p) out.push_back(probe_grant(p));
  for (auto& g : out) g.subject = subject_of(g.name);
  return out;
}

core::Result<Grant> grant_for(const std::string& name, const SwarmShape& shape) {
  auto no_role = [&](const std::string& why) {
    return core::Error{"'" + name + "' is no process of this swarm: " + why};
  };
  Grant g;
  uint32_t n = 0;
  if (name == "ground") {
    g = ground_grant();
  } else if (name == kMonitorIdentity) {
    g = monitor_grant();
  } else if (name.rfind("uav-", 0) == 0 && parse_index(name.substr(4), n)) {
    if (n >= shape.uavs) return no_role("it has " + std::to_string(shape.uavs) + " UAVs");
    if (shape.regions == 0) return no_role("it has no regions");
    g = uav_grant(n, shape.regions);
  } else if (name.rfind("probe-", 0) == 0 && parse_index(name.substr(6), n)) {
    if (n >= shape.probes) return no_role("it has " + std::to_string(shape.probes) + " probe identities");
    g = probe_grant(n);
  } else if (name.rfind("place-", 0) == 0) {
    const std::string rest = name.substr(6);
    const auto dot = rest.find(".r");
    uint32_t replica = 0;
    if (!parse_index(rest.substr(0, dot), n) ||
        (dot != std::string::npos && !parse_index(rest.substr(dot + 2), replica))) {
      return no_role("expected place-R or place-R.rK");
    }
    if (n >= shape.regions) return no_role("it has " + std::to_string(shape.regions) + " regions");
    if (replica > shape.standby) return no_role("it has " + std::to_string(shape.standby) + " standby per region");
    g = place_grant(name, n);
  } else {
    return no_role("names are uav-N, place-R, place-R.rK, ground, monitor, probe-N");
  }
  g.subject = subject_of(g.name);
  return g;
}

std::string governance_xml(Protection p) {
  const std::string kind = p == Protection::Encrypt ? "ENCRYPT" : p == Protection::Sign ? "SIGN" : "NONE";
  const std::string on = p == Protection::None ? "false" : "true";
  std::string x;
  x += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x += "<!-- pheromesh swarm governance (protection: ";
  x += to_string(p);
  x += "); written by pheromesh security init -->\n";
  x += "<dds xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" "
       "xsi:noNamespaceSchemaLocation=\"http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd\">\n";
  x += "  <domain_access_rules>\n    <domain_rule>\n      ";
  x += kDomains;
  x += "\n";
  // Nobody without a certificate of the swarm's CA joins; every topic is
  // read- and write-access controlled by the permissions.
  x += "      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>\n";
  x += "      <enable_join_access_control>true</enable_join_access_control>\n";
  x += "      <discovery_protection_kind>" + kind + "</discovery_protection_kind>\n";
  x += "      <liveliness_protection_kind>" + kind + "</liveliness_protection_kind>\n";
  // Whole-message protection would add a second transform to every datagram;
  // submessages and payloads are protected per topic below.
  x += "      <rtps_protection_kind>NONE</rtps_protection_kind>\n";
  x += "      <topic_access_rules>\n        <topic_rule>\n";
  x += "          <topic_expression>*</topic_expression>\n";
  x += "          <enable_discovery_protection>" + on + "</enable_discovery_protection>\n";
  x += "          <enable_liveliness_protection>" + on + "</enable_liveliness_protection>\n";
  x += "          <enable_read_access_control>true</enable_read_access_control>\n";
  x += "          <enable_write_access_control>true</enable_write_access_control>\n";
  x += "          <metadata_protection_kind>" + kind + "</metadata_protection_kind>\n";
  x += "          <data_protection_kind>" + kind + "</data_protection_kind>\n";
  x += "        </topic_rule>\n      </topic_access_rules>\n";
  x += "    </domain_rule>\n  </domain_access_rules>\n</dds>\n";
  return x;
}

std::string permissions_xml(const Grant& g, const std::string& not_before, const std::string& not_after) {
  std::string x;
  x += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x += "<!-- pheromesh permissions of ";
  xml_escape_into(x, g.name);
  x += "; written by pheromesh security init -->\n";
  x += "<dds xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" "
       "xsi:noNamespaceSchemaLocation=\"http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd\">\n";
  x += "  <permissions>\n    <grant name=\"";
  xml_escape_into(x, g.name);
  x += "\">\n      <subject_name>";
  xml_escape_into(x, g.subject);
  x += "</subject_name>\n      <validity><not_before>" + not_before + "</not_before><not_after>" + not_after +
       "</not_after></validity>\n";
  x += "      <allow_rule>\n        ";
  x += kDomains;
  x += "\n";
  rules_into(x, "publish", g.publish);
  rules_into(x, "subscribe", g.subscribe);
  x += "      </allow_rule>\n";
  // Anything not allowed above (another topic, another partition) is denied.
  x += "      <default>DENY</default>\n    </grant>\n  </permissions>\n</dds>\n";
  return x;
}

SecurityFiles security_files(const std::string& dir, const std::string& identity) {
  const std::filesystem::path d(dir);
  return {(d / "ca.pem").string(), (d / "governance.p7s").string(), (d / identity / "cert.pem").string(),
          (d / identity / "key.pem").string(), (d / identity / "permissions.p7s").string()};
}

core::Result<SecurityFiles> find_security_files(const std::string& dir, const std::string& identity) {
  SecurityFiles f = security_files(dir, identity);
  const std::string make = "pheromesh security init " + dir + " --scenario SCENARIO (with the swarm's --uavs/--standby)";
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    return core::Error{"security directory " + dir + " does not exist; create it with: " + make};
  }
  for (const std::string* p : {&f.ca, &f.governance, &f.cert, &f.key, &f.permissions}) {
    if (!std::filesystem::is_regular_file(*p, ec)) {
      return core::Error{"no DDS Security identity '" + identity + "': " + *p + " is missing; create it with: " + make};
    }
  }
  return f;
}

std::optional<std::string> check_secure_profile(const std::string& vendor, const std::string& profile, bool cell) {
  if (vendor != "fastdds" || cell) return std::nullopt;
  if (profile != "onehost" && profile != "netns" && profile != "lan") return std::nullopt;
  return "--secure over Fast DDS needs unicast discovery: profile cells (the default), onehost-unicast or "
         "lan-unicast, not " +
         profile +
         ": Fast DDS 2.9 handles a new secure participant in two threads at once when discovery also comes by "
         "multicast, and pairs of processes then never authenticate or a process aborts (docs/security.md, "
         "\"Fast DDS 2.9.1: one discovery socket\")";
}

}  // namespace pheromesh::bus
