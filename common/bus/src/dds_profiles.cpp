#include "dds_profiles.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "dds_profiles_data.hpp"

namespace pheromesh::bus {
namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read DDS profile '" + path + "': " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t comma = s.find(',', start);
    const std::string part = s.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (!part.empty()) out.push_back(part);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

bool is_cyclone_xml(const std::string& text) { return text.find("<CycloneDDS") != std::string::npos; }
bool is_fastdds_xml(const std::string& text) {
  return text.find("<dds") != std::string::npos || text.find("<profiles") != std::string::npos;
}

// The file among `profile`'s comma-separated files whose root element is the
// vendor's; its text in `text`.
template <typename IsVendor>
std::string pick_file(const std::string& profile, const char* vendor, const char* expected, IsVendor&& is_vendor,
                      std::string& text) {
  const std::vector<std::string> files = split_commas(profile);
  for (const auto& f : files) {
    std::string t = read_file(f);
    if (is_vendor(t)) {
      text = std::move(t);
      return f;
    }
  }
  throw std::runtime_error("DDS profile '" + profile + "': no " + vendor + " configuration among its files (expected a " +
                           expected + " root element; give one file per vendor, separated by commas)");
}

}  // namespace

bool takes_peers(const std::string& profile) { return profile == "lan" || profile == "lan-unicast"; }

void check_peers(const std::string& profile, const std::vector<std::string>& peers) {
  if (!peers.empty() && !takes_peers(profile)) {
    throw std::runtime_error(
        "DDS peers (--dds-peers, $PHEROMESH_DDS_PEERS) are for the lan and lan-unicast profiles, not '" + profile +
        "'");
  }
}

std::string cyclone_heartbeat(uint32_t swarm_processes) {
  return swarm_processes > kQuietHeartbeatAbove ? "1s" : "";
}

FastDdsWriterPace fastdds_writer_pace(uint32_t swarm_processes) {
  if (swarm_processes > kQuietHeartbeatAbove) {
    return {std::chrono::milliseconds(1000), false};
  }
  return {};
}

namespace {

// The one-host profile `xml` with the heartbeat for `swarm_processes`.
std::string with_heartbeat(std::string xml, const std::string& profile, uint32_t swarm_processes) {
  const std::string hb = cyclone_heartbeat(swarm_processes);
  if (hb.empty()) return xml;
  const std::size_t at = xml.find("</Internal>");
  if (at == std::string::npos) throw std::logic_error("built-in profile '" + profile + "' has no <Internal>");
  xml.insert(at, "<HeartbeatInterval>" + hb + "</HeartbeatInterval>");
  return xml;
}

}  // namespace

std::string cyclone_config(const std::string& profile, const std::vector<std::string>& peers,
                           uint32_t swarm_processes) {
  check_peers(profile, peers);
  if (takes_peers(profile)) {
    std::string xml = profile == "lan" ? detail::kCycloneLanXml : detail::kCycloneLanUnicastXml;
    if (peers.empty()) return xml;
    // One <Peer> per address, into <Discovery> (cyclone-lan-unicast.xml).
    std::string list = "<Peers>";
    for (const auto& p : peers) list += "<Peer Address=\"" + p + "\"/>";
    list += "</Peers>";
    const std::size_t at = xml.find("</Discovery>");
    if (at == std::string::npos) throw std::logic_error("built-in profile '" + profile + "' has no <Discovery>");
    xml.insert(at, list);
    return xml;
  }
  // Vendor defaults, plus the keyhash that Fast DDS needs to notice Cyclone's
  // deleted readers (see cyclone-onehost.xml).
  if (profile == "default" || profile.empty()) {
    return R"(<CycloneDDS><Domain Id="any"><Internal><GenerateKeyhash>true</GenerateKeyhash></Internal></Domain></CycloneDDS>)";
  }
  if (profile == "onehost") return with_heartbeat(detail::kCycloneOneHostXml, profile, swarm_processes);
  if (profile == "onehost-unicast") {
    return with_heartbeat(detail::kCycloneOneHostUnicastXml, profile, swarm_processes);
  }
  if (profile == "netns") return detail::kCycloneNetnsXml;
  std::string text;
  pick_file(profile, "Cyclone DDS", "<CycloneDDS>", is_cyclone_xml, text);
  return text;
}

FastDdsProfile fastdds_profile(const std::string& profile, const std::vector<std::string>& peers) {
  check_peers(profile, peers);
  FastDdsProfile p;
  p.peers = peers;
  if (profile == "lan") return {detail::kFastDdsLanXml, "pheromesh-lan", "", peers};
  if (profile == "lan-unicast") return {detail::kFastDdsLanUnicastXml, "pheromesh-lan-unicast", "", peers};
  if (profile == "default" || profile.empty()) return p;
  if (profile == "onehost") return {detail::kFastDdsOneHostXml, "pheromesh-onehost", "", {}};
  if (profile == "onehost-unicast") return {detail::kFastDdsOneHostUnicastXml, "pheromesh-onehost-unicast", "", {}};
  if (profile == "netns") return {detail::kFastDdsNetnsXml, "pheromesh-netns", "", {}};
  std::string text;
  p.file = pick_file(profile, "Fast DDS", "<dds> or <profiles>",
                     [](const std::string& t) { return is_fastdds_xml(t) && !is_cyclone_xml(t); }, text);
  return p;
}

}  // namespace pheromesh::bus
