#include "dds_plan.hpp"

#include <algorithm>

namespace pheromesh::cli {
namespace {

std::string alternate(const std::string& v, uint32_t index, bool even_is_cyclone) {
  if (v != "mixed") return v;
  return ((index % 2 == 0) == even_is_cyclone) ? "cyclone" : "fastdds";
}

std::string role_text(const std::string& v, bool even_is_cyclone) {
  if (v != "mixed") return v;
  return even_is_cyclone ? "cyclone/fastdds" : "fastdds/cyclone";
}

}  // namespace

std::string DdsPlan::vendor_of(const std::string& role, uint32_t index) const {
  if (role == "ground") return ground == "mixed" ? "cyclone" : ground;
  if (role == "place") return alternate(place, index, true);
  return alternate(uav, index, false);
}

std::string DdsPlan::describe() const {
  if (single_vendor()) return ground;
  return "mixed (ground " + vendor_of("ground", 0) + ", place agents " + role_text(place, true) + ", uavs " +
         role_text(uav, false) + ")";
}

core::Result<DdsPlan> parse_dds_plan(const std::string& spec, const std::vector<std::string>& vendors) {
  std::vector<std::string> allowed = vendors;
  allowed.emplace_back("mixed");
  auto known = [&](const std::string& v) { return std::find(allowed.begin(), allowed.end(), v) != allowed.end(); };
  std::string list;
  for (const auto& v : allowed) list += (list.empty() ? "" : ", ") + v;
  const std::string usage = " (expected one of " + list + ", or per role: ground=V,place=V,uav=V)";

  DdsPlan plan;
  if (spec.find('=') == std::string::npos) {
    if (!known(spec)) return core::Error{"--dds: unknown vendor '" + spec + "'" + usage};
    plan.ground = plan.place = plan.uav = spec;
    return plan;
  }
  std::size_t start = 0;
  while (start <= spec.size()) {
    const std::size_t comma = spec.find(',', start);
    const std::string item = spec.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos) return core::Error{"--dds: '" + item + "' is not ROLE=VENDOR" + usage};
    const std::string role = item.substr(0, eq);
    const std::string vendor = item.substr(eq + 1);
    if (!known(vendor)) return core::Error{"--dds: unknown vendor '" + vendor + "' for " + role + usage};
    if (role == "ground") {
      plan.ground = vendor;
    } else if (role == "place") {
      plan.place = vendor;
    } else if (role == "uav") {
      plan.uav = vendor;
    } else {
      return core::Error{"--dds: unknown role '" + role + "' (roles: ground, place, uav)"};
    }
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return plan;
}

}  // namespace pheromesh::cli
