// `pheromesh run --dds`: which DDS vendor each spawned process uses.
//   cyclone | fastdds        every process
//   mixed                    vendors alternate: the ground station on Cyclone,
//                            place agent i on Cyclone if i is even and Fast DDS
//                            if odd, UAV j the other way round (Fast DDS if even)
//   ground=V,place=V,uav=V   per role, V one of cyclone, fastdds, mixed
//                            (alternating within the role as above); a role
//                            left out runs on Cyclone
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "pheromesh/core/result.hpp"

namespace pheromesh::cli {

struct DdsPlan {
  std::string ground = "cyclone";
  std::string place = "cyclone";
  std::string uav = "cyclone";

  // The vendor of process `index` of `role` ("ground", "place", "uav").
  [[nodiscard]] std::string vendor_of(const std::string& role, uint32_t index) const;
  // E.g. "mixed (ground cyclone, place agents cyclone/fastdds, uavs fastdds/cyclone)".
  [[nodiscard]] std::string describe() const;
  [[nodiscard]] bool single_vendor() const { return ground == place && place == uav && ground != "mixed"; }
};

// `vendors`: the vendors this build has. Errors name --dds and what is allowed.
core::Result<DdsPlan> parse_dds_plan(const std::string& spec, const std::vector<std::string>& vendors);

}  // namespace pheromesh::cli
