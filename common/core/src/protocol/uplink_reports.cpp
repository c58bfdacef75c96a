#include "pheromesh/core/uplink_reports.hpp"

namespace pheromesh::core {

std::optional<PhaseDoneMsg> UplinkReports::on_state(const UavStateMsg& st, std::span<const DepositMsg> carried) {
  auto [it, fresh] = uplinks_.try_emplace(st.uav);
  Uplink& u = it->second;
  if (!fresh && st.tick < u.tick) return std::nullopt;
  if (fresh || st.tick > u.tick) u = Uplink{st.tick, st.tick_deposits, st.broadcasts, {}, {}};
  for (const DepositMsg& d : carried) {
    if (d.uav == st.uav && u.seqs.insert(d.seq).second) ++u.per_region[d.region];
  }
  if (u.seqs.size() < u.expected) return std::nullopt;
  PhaseDoneMsg m{process_key(kRoleUav, st.uav), st.tick, static_cast<uint8_t>(ClockPhase::Uav), u.broadcasts, {}};
  for (const auto& [region, n] : u.per_region) m.deposits.push_back({region, n});
  return m;
}

PhaseDoneMsg UplinkReports::on_refused(const UavStateMsg& st) {
  return {process_key(kRoleUav, st.uav), st.tick, static_cast<uint8_t>(ClockPhase::Uav), st.broadcasts, {}};
}

}  // namespace pheromesh::core
