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
//
// The lifecycle, as ARGoS's init / step / destroy. `pheromesh sim` is this
// sequence run through (run()); the Python package's pheromesh.Simulation
// drives it a tick at a time and perturbs the run between ticks:
//   Simulator sim(s);  sim.set_faults(f, standby);   the swarm and its faults
//   while (!sim.done()) sim.advance();               ticks 0..scenario.ticks, one a call
//       between two ticks: sim.add_faults(g)         events timed at next_tick() or later
//   sim.finish();                                    the final accounting, once
// A fault added between ticks changes the run exactly as the same event in
// the schedule given before tick 0 does (SteppedSimulator tests): nothing the
// simulator does before a fault's tick depends on the fault.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
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

  // Runs ticks 0..scenario.ticks and finishes; `on_tick(k)` (optional) is
  // called after each. The same as advance() until done(), then finish().
  void run(const std::function<void(uint32_t)>& on_tick = {});
  // The tick advance() runs next: 0 before the first, scenario.ticks + 1 once
  // every tick has run.
  [[nodiscard]] uint32_t next_tick() const { return next_tick_; }
  // Every tick of the run (0..scenario.ticks) has run.
  [[nodiscard]] bool done() const { return next_tick_ > scenario_.ticks; }
  [[nodiscard]] bool finished() const { return finished_; }
  // Runs tick next_tick(); false (and nothing runs) once done() or finished().
  bool advance();
  // The final accounting, as the processes send it when a run ends: the place
  // agents' last health records, every live UAV's finished state, the field
  // summary. False (and nothing changes) before done() or a second time.
  bool finish();
  // One tick (both phases) numbered `tick`, outside the lifecycle (a study
  // that runs past scenario.ticks); next_tick() becomes tick + 1.
  void step(uint32_t tick);

  // The faults of the coming run (call before run()/step()). Kills timed in
  // ticks change the run as described above; `standby` (or a `standby
  // place:R` event timed before R's kill) means a standby place agent takes
  // over, which changes nothing. Returns one note per event that does not
  // change simulated numbers (stop, partition, loss, covered kills), or an
  // error for what the simulator cannot model: wall-clock times, restarts,
  // killing the ground station, targets outside the swarm or the map.
  Result<std::vector<std::string>> set_faults(const FaultSchedule& schedule, bool standby);
  // More faults between ticks (the console's kill, `--faults` events given
  // late): every event must be timed at next_tick() or later, in ticks; they
  // join the schedule as if given before tick 0 (`standby` as the last
  // set_faults, else the scenario's). Returns the notes of the new events, or
  // an error that changes nothing: a tick already run, an unknown target, a
  // UAV or place agent already killed, what set_faults refuses, a finished run.
  Result<std::vector<std::string>> add_faults(const FaultSchedule& more);
  // Every fault event of the run so far (set_faults and add_faults, by time).
  [[nodiscard]] const FaultSchedule& faults() const { return faults_; }
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
  // Built on demand: a tick builds only the tiles some UAV reads.
  [[nodiscard]] const std::map<std::pair<int32_t, int32_t>, std::vector<TileMsg>>& tiles() const;
  [[nodiscard]] const ScenarioConfig& scenario() const { return scenario_; }
  [[nodiscard]] const World& world() const { return world_; }
  // Final field value of layer `layer` at c (from the place agent owning c).
  // Between ticks: the field the place agents hold after the last tick.
  [[nodiscard]] float field_value(int layer, Cell c) const;
  // Layer `layer` of the whole map, row-major [y][x], into `out` (width *
  // height values), region by region.
  // False (nothing written) for a layer it does not have or a size that is not
  // the map's.
  bool gather_layer(int layer, std::span<float> out) const;
  // Whether UAV u acts in tick next_tick() (false once its kill tick came).
  [[nodiscard]] bool uav_alive(uint32_t u) const { return !uav_gone(u, next_tick_); }
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
  // The tiles the live place agents published at the end of place tick
  // tiles_tick_ (none before the first), built when first read: a UAV reads
  // the few around it, and building every tile of a 400 x 400 map each tick
  // cost more than flying the swarm (issue 44). tile -> its layers.
  mutable std::map<std::pair<int32_t, int32_t>, std::vector<TileMsg>> tiles_;
  mutable bool tiles_complete_ = false;  // tiles_ holds every published tile
  std::optional<uint32_t> tiles_tick_;   // the place tick of the published tiles
  std::vector<uint8_t> tiles_live_;      // per region: it published tiles at tiles_tick_
  // The layers of tile t as published (nullptr: no live place agent published it).
  const std::vector<TileMsg>* published_tile(TileCoord t) const;
  std::vector<std::vector<DepositMsg>> inbox_;                         // per region
  std::map<std::pair<int32_t, int32_t>, std::vector<UavStateMsg>> states_by_tile_;  // UAV states of the last tick
  std::vector<BroadcastMsg> broadcasts_;                                            // broadcasts of the last tick
  uint64_t uav_steps_ = 0;
  // Faults: the tick each UAV / region is gone from (absent: never).
  std::map<uint32_t, uint32_t> uav_kill_;
  std::map<RegionId, uint32_t> region_kill_;
  std::set<RegionId> standby_;  // killed regions a standby took over: they live on
  // Every region's ring of the last tick, by region (moved in each tick, not
  // copied): a dead region's stays the one of its last tick (what its
  // neighbours' diffusion uses). Kept for every region, not only those the
  // schedule kills, so that nothing before a kill's tick depends on the
  // schedule (add_faults).
  std::vector<HaloMsg> last_rings_;
  FaultSchedule faults_;
  std::optional<bool> standby_all_;       // set_faults' `standby`
  std::vector<std::string> fault_notes_;  // set_faults' notes of faults_
  uint32_t next_tick_ = 0;
  bool finished_ = false;
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
  // answer (UavStateMsg::implausible). `carried` (if given): what becomes of
  // the deposits the state carries (core::carried_deposits).
  bool through_gateway(RegionId gateway, UavStateMsg s, uint32_t tick, CarriedDeposits* carried = nullptr);
  [[nodiscard]] HealthMsg health_of(const PlaceCore& p, uint32_t tick, bool final) const;
  // step() in its parts, in order: the kills of `tick` (for the metrics),
  // the UAV phase (each live UAV: its view, then its flight), the place
  // phase, and what the tick publishes (tiles, health).
  void note_kills(uint32_t tick);
  void uav_phase(uint32_t tick);
  void show_view(std::size_t uav, uint32_t tick);
  void fly_uav(std::size_t uav, uint32_t tick, UavCore::Output& out, std::vector<UavStateMsg>& states,
               std::vector<BroadcastMsg>& broadcasts);
  void place_phase(uint32_t tick);
  void publish_tick(uint32_t tick);

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
