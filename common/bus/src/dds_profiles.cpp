#include "dds_profiles.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "dds_profiles_data.hpp"

namespace pheromesh::bus {

std::string cyclone_config(const std::string& profile) {
  if (profile == "default" || profile.empty()) return {};
  if (profile == "onehost") return detail::kCycloneOneHostXml;
  if (profile == "onehost-unicast") return detail::kCycloneOneHostUnicastXml;
  std::ifstream in(profile);
  if (!in) throw std::runtime_error("cannot read DDS profile '" + profile + "': " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace pheromesh::bus
