#include "pheromesh/core/sender_judge.hpp"

#include <string>

namespace pheromesh::core {

namespace {

std::string place_text(RegionId region, uint32_t replica) {
  return replica > 0 ? "standby " + std::to_string(replica) + " of region " + std::to_string(region)
                     : "place agent " + std::to_string(region);
}

// `participant` holds a replica of region `r`, or none of them is held.
bool speaks_for_region(const PlaceVouch& places, RegionId r, uint64_t participant, const SwarmNames& names) {
  for (uint32_t k = 0; k < names.replicas; ++k) {
    if (places.speaks_for(place_id(r, static_cast<uint16_t>(k)), participant)) return true;
  }
  return false;
}

}  // namespace

IntakeVerdict check_place_id(RegionId region, uint32_t replica, const SwarmNames& names, const char* what) {
  if (region < names.regions && replica < names.replicas) return IntakeVerdict::take();
  std::string why = std::string(what) + " of " + place_text(region, replica) + ", which this run does not have (";
  why += std::to_string(names.regions) + " regions, ";
  why += names.replicas > 1 ? "one standby each)" : "no standbys)";
  return IntakeVerdict::refuse(Refusal::UnknownPlace, std::move(why));
}

IntakeVerdict judge_place_sample(PlaceVouch& places, RegionId region, uint16_t replica, uint64_t participant,
                                 PlaceVouch::Clock::time_point now, const SwarmNames& names, bool new_life,
                                 const char* what) {
  if (auto v = check_place_id(region, replica, names, what); !v.taken()) return v;
  if (places.claim(place_id(region, replica), participant, now, new_life)) return IntakeVerdict::take();
  return IntakeVerdict::refuse(Refusal::ForeignWriter, std::string(what) + " of " + place_text(region, replica) +
                                                           " from a process other than the one heard as it");
}

IntakeVerdict judge_report(const PhaseDoneMsg& m, const PlaceVouch& places, const SwarmNames& names) {
  const uint32_t role = m.process >> 24U;
  const uint32_t id = m.process & 0xFFFFFFU;
  if (role == kRolePlace) {
    const RegionId region = place_id_region(id);
    const uint16_t replica = place_id_replica(id);
    if (auto v = check_place_id(region, replica, names, "a lockstep report"); !v.taken()) return v;
    if (places.speaks_for(id, m.participant)) return IntakeVerdict::take();
    return IntakeVerdict::refuse(Refusal::ForeignReport, "a lockstep report of " + place_text(region, replica) +
                                                             " from a process other than the one heard as it");
  }
  if (role != kRoleUav) return IntakeVerdict::drop("a lockstep report of no role (" + std::to_string(role) + ")");
  if (auto why = check_uav_id(id, names.uavs)) return IntakeVerdict::refuse(Refusal::UnknownUav, *why);
  const RegionId home = home_region(id, names.regions);
  const RegionId backup = backup_region(id, names.regions);
  if (speaks_for_region(places, home, m.participant, names) ||
      speaks_for_region(places, backup, m.participant, names)) {
    return IntakeVerdict::take();
  }
  return IntakeVerdict::refuse(Refusal::ForeignReport, "a lockstep report of uav " + std::to_string(id) +
                                                           " from a process that is not its home's (" +
                                                           std::to_string(home) + ") nor its backup's (" +
                                                           std::to_string(backup) + ")");
}

IntakeVerdict judge_uplink(const char* what, uint32_t uav, RegionId self, const SwarmNames& names,
                           bool from_uav_process, Refusal not_gateway, Refusal foreign) {
  const std::string of = std::string(what) + " of uav " + std::to_string(uav);
  if (auto why = check_uav_id(uav, names.uavs)) return IntakeVerdict::refuse(Refusal::UnknownUav, of);
  if (home_region(uav, names.regions) != self && backup_region(uav, names.regions) != self) {
    return IntakeVerdict::refuse(
        not_gateway, of + " at place agent " + std::to_string(self) + ", which is neither its home nor its backup");
  }
  if (!from_uav_process) {
    return IntakeVerdict::refuse(foreign, of + " from a process other than the one its states come from");
  }
  return IntakeVerdict::take();
}

IntakeVerdict judge_uav_report(const PhaseDoneMsg& m, RegionId self, const SwarmNames& names, bool from_uav_process) {
  if (m.process >> 24U != kRoleUav) {
    return IntakeVerdict::drop("a report that is not a UAV's sent to a place agent's UAV reports");
  }
  return judge_uplink("a lockstep report", m.process & 0xFFFFFFU, self, names, from_uav_process, Refusal::ForeignReport,
                      Refusal::ForeignReport);
}

IntakeVerdict judge_lockstep_forward(const DepositMsg& d, uint32_t place_tick, bool gateway_of_uav,
                                     bool refused_anyway) {
  if (gateway_of_uav) {
    return IntakeVerdict::refuse(Refusal::ForeignWriter,
                                 "a deposit of uav " + std::to_string(d.uav) + " (seq " + std::to_string(d.seq) +
                                     ") forwarded to its own gateway, which takes its deposits from its states");
  }
  if (d.tick != place_tick && !refused_anyway) {
    return IntakeVerdict::refuse(Refusal::UnannouncedDeposit,
                                 "a deposit of uav " + std::to_string(d.uav) + " (seq " + std::to_string(d.seq) +
                                     ") of tick " + std::to_string(d.tick) + " forwarded in the place phase of tick " +
                                     std::to_string(place_tick) + ", which announced none of another tick");
  }
  return IntakeVerdict::take();
}

}  // namespace pheromesh::core
