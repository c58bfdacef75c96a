// The in-process simulator: the same UavCore and PlaceCore the processes run,
// wired together in memory with the lockstep schedule (DESIGN.md, "Time"):
// tick k = UAV phase (read tiles of place tick k-1, decide, move, deposit),
// then place phase (apply exactly the deposits of tick k in canonical order,
// exchange halos of tick k, update, publish tiles of tick k). No DDS, no
// threads: deterministic for a scenario and seed.
//
// Faults (set_faults; docs/faults.md, "Faults in the simulator") follow the
// meaning faults.hpp gives a kill at tick k, which a lockstep run of the
// processes gives too. Views are numbered by place tick: the view of tick t is
// composed at the end of tick t and read by its UAV at tick t+1.
//   kill uav:U @kt     U steps in ticks 0..k-1 only: its state of tick k-1 is
//                      the last one in any view (the views of tick k-1), it
//                      deposits, detects and covers nothing from tick k on.
//   kill place:R @kt   (no standby) R runs its place phase in ticks 0..k-1
//                      only. Its tiles and its halo ring stay those of tick
//                      k-1 (its neighbours keep diffusing against that ring);
//                      every deposit made at tick >= k into R is lost, and
//                      so is every deposit made at tick >= k by a UAV homed on
//                      R (it goes through its home); the views of tick >= k of
//                      R's home UAVs are empty (they read no tiles and no
//                      neighbours from tick k+1 on; broadcasts do not go
//                      through the home and still arrive), and their states of
//                      tick >= k reach no other view (the home publishes
//                      them with its field). The ground station still hears
//                      them: they keep covering cells and detecting targets.
// Plausibility: each UAV's state goes through its gateway's judge, as in the
// processes (core::StateGate): one further from its last accepted state than
// the policy's max_step allows is refused and counted by the gateway region,
// reaches no view, and its UAV reads an empty view next tick; the recorder
// hears it as the gateway's answer. Its deposits go on as a state's do.
// A lost deposit is sent and never received by any place agent
// (RunRecorder::deposits_lost), so a run still balances: sent == applied +
// rejected + lost.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "pheromesh/core/faults.hpp"
#include "pheromesh/core/intake.hpp"
#include "pheromesh/core/place_core.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/uav_core.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::core {

class Simulator {
 public:
  explicit Simulator(ScenarioConfig scenario);
  // world_ and the agents point into this object: pinned in memory.
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  // Runs ticks 0..scenario.ticks; `on_tick(k)` (optional) is called after each.
  void run(const std::function<void(uint32_t)>& on_tick = {});
  // One tick (both phases).
  void step(uint32_t tick);

  // The faults of the coming run (call before run()/step()). Kills timed in
  // ticks change the run as described above; `standby` (or a `standby
  // place:R` event timed before R's kill) means a standby place agent takes
  // over, which changes nothing. Returns one note per event that does not
  // change simulated numbers (stop, partition, loss, covered kills), or an
  // error for what the simulator cannot model: wall-clock times, restarts,
  // killing the ground station, targets outside the swarm or the map.
  Result<std::vector<std::string>> set_faults(const FaultSchedule& schedule, bool standby);
  // When UAV u stops acting / region r stops ticking (nullopt: never).
  [[nodiscard]] std::optional<uint32_t> uav_kill_tick(uint32_t u) const;
  [[nodiscard]] std::optional<uint32_t> region_kill_tick(RegionId r) const;
  // One UAV's core, for tests and traces.
  [[nodiscard]] const UavCore& uav(uint32_t u) const { return *uavs_.at(u); }

  [[nodiscard]] const RunRecorder& recorder() const { return recorder_; }
  // Keep every UAV's position of every tick (RunRecorder::tracks); call before run().
  void keep_tracks() { recorder_.keep_tracks(); }
  // The tiles every place agent published at the end of the last tick (what
  // the UAVs read next), by (tx, ty): `pheromesh sim --record`'s console.
  [[nodiscard]] const std::map<std::pair<int32_t, int32_t>, std::vector<TileMsg>>& tiles() const { return tiles_; }
  [[nodiscard]] const ScenarioConfig& scenario() const { return scenario_; }
  [[nodiscard]] const World& world() const { return world_; }
  // Final field value of layer `layer` at c (from the place agent owning c).
  [[nodiscard]] float field_value(int layer, Cell c) const;
  [[nodiscard]] int layer_count() const;
  [[nodiscard]] uint64_t uav_steps() const { return uav_steps_; }

 private:
  ScenarioConfig scenario_;
  MapGeometry geo_;
  World world_;
  RunRecorder recorder_;
  std::vector<std::unique_ptr<UavCore>> uavs_;
  std::vector<std::unique_ptr<PlaceCore>> places_;
  std::vector<uint64_t> deposits_sent_;
  std::vector<uint64_t> tile_samples_;
  std::map<std::pair<int32_t, int32_t>, std::vector<TileMsg>> tiles_;  // tile -> its layers, latest place tick
  std::vector<std::vector<DepositMsg>> inbox_;                         // per region
  std::map<std::pair<int32_t, int32_t>, std::vector<UavStateMsg>> states_by_tile_;  // UAV states of the last tick
  std::vector<BroadcastMsg> broadcasts_;                                            // broadcasts of the last tick
  uint64_t uav_steps_ = 0;
  // Faults: the tick each UAV / region is gone from (absent: never).
  std::map<uint32_t, uint32_t> uav_kill_;
  std::map<RegionId, uint32_t> region_kill_;
  std::set<RegionId> standby_;  // killed regions a standby took over: they live on
  // A region that will die keeps its last ring (what its neighbours' diffusion uses).
  std::map<RegionId, HaloMsg> last_ring_;
  // The one plausibility rule, as each UAV's gateway applies it in the
  // processes (core::StateGate, docs/architecture.md "Plausibility"): per
  // gateway region its judge, the last state it accepted of each UAV and the
  // states it refused (counted in its health); the UAVs owed an empty view.
  PolicyTraits traits_;
  std::vector<StateGate> gates_;
  std::map<std::pair<RegionId, uint32_t>, UavStateMsg> accepted_;
  std::map<uint32_t, UavStateMsg> last_accepted_;  // per UAV, by any gateway: where its deposits are judged from
  std::vector<RefusalCounts> gate_refused_;
  std::vector<uint8_t> empty_view_;  // per UAV, 0 or 1 (not vector<bool>: std::exchange)
  // The state `s` of UAV `id` through its gateway `gateway` at `tick`: true
  // if it was accepted; a refused one goes to the recorder as the gateway's
  // answer (UavStateMsg::implausible).
  bool through_gateway(RegionId gateway, UavStateMsg s, uint32_t tick);
  [[nodiscard]] HealthMsg health_of(const PlaceCore& p, uint32_t tick, bool final) const;

  [[nodiscard]] bool uav_gone(uint32_t u, uint32_t tick) const;
  [[nodiscard]] bool region_dead(RegionId r, uint32_t tick) const;
};

// `pheromesh validate`'s trial of a policy's max_step (issue 42): the
// scenario flown in the simulator for at most `ticks` ticks, and for each UAV
// whose states its gateway refused the first refusal in plain words
// (describe_first_refusal); nothing when none was refused. An exception from
// the policy is a line of its own (the trial cannot judge it).
std::vector<std::string> max_step_trial(ScenarioConfig scenario, uint32_t ticks);

}  // namespace pheromesh::core
