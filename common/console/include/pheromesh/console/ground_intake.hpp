// What the ground station does with every sample it receives, without DDS:
// the checks on each state, broadcast, detection, target event, health,
// field, tile, departure and PhaseDone (messages.hpp, plausibility.hpp), and
// who is told of it - the run recorder, the lockstep conductor, the run book
// (fields), the frame builder and the uncertainty plot. The ground station
// takes the samples from its bus, hands them over with the time, and logs
// the notes returned. Follows LockstepConductor and FrameBuilder.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "pheromesh/console/frame_builder.hpp"
#include "pheromesh/console/uncertainty.hpp"
#include "pheromesh/core/conductor.hpp"
#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/plausibility.hpp"
#include "pheromesh/core/run_book.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::console {

// What the ground station received since it last looked, by kind.
struct GroundSamples {
  std::vector<core::UavStateMsg> states;
  std::vector<core::BroadcastMsg> broadcasts;
  std::vector<uint32_t> departed_uavs;
  std::vector<core::DetectionMsg> detections;
  std::vector<core::TargetEventMsg> target_events;
  std::vector<core::HealthMsg> healths;
  std::vector<core::FieldMsg> fields;
  std::vector<core::TileMsg> tiles;
  std::vector<uint32_t> departed_places;  // core::place_id
  std::vector<core::PhaseDoneMsg> phase_dones;
  void clear();
};

// One thing worth a log line; `text` is the line.
struct IntakeNote {
  enum class Kind : uint8_t {
    StateDropped,    // malformed (the first 3 samples rejected)
    StateRefused,    // implausible (the first 5 refusals)
    SampleRefused,   // a broadcast, field or tile refused (the first 5 refusals)
    TileDropped,     // malformed (the first 3 samples rejected)
    UavBack,         // a UAV whose liveliness had lapsed is heard again
    UavLost,         // a UAV's liveliness lapsed before it finished
    TargetAcquired,  // a target detected for the first time
    PlaceBack,       // a place replica that had been lost is heard again
    OwnerRegained,   // a region's output is owned by a lower replica again
    PlaceLost,       // a place replica's liveliness lapsed before it finished
  };
  enum class Level : uint8_t { Info, Warn };
  Kind kind;
  Level level;
  std::string text;
};

class GroundIntake {
 public:
  using Clock = std::chrono::steady_clock;
  using Notes = std::vector<IntakeNote>;
  // Place agents with hot standby replicas: a lost replica is not waited for
  // again by the conductor.
  enum class Standby : uint8_t { None, Hot };

  // What the intake feeds; all outlive it.
  struct Parts {
    core::RunRecorder& rec;
    core::LockstepConductor& conductor;
    core::RunBook& book;
    FrameBuilder& frames;
    const core::World& world;  // targets, with those added during the run
  };

  GroundIntake(const core::ScenarioConfig& scenario, Parts parts, Standby standby);
  // The console's uncertainty plot, once it exists (null: none).
  void set_uncertainty(UncertaintyTracker* u) { uncertainty_ = u; }

  // Hands every sample of `in` to whom it concerns, in the order of the
  // members of GroundSamples; samples of a tick above `tick_ceiling`
  // (RunBook::tick_ceiling) are refused. Moves the tiles out of the fields.
  Notes take(GroundSamples& in, uint32_t tick_ceiling, Clock::time_point now);
  // End of a run: judges the detections still waiting (RunRecorder) and
  // reports the targets they acquired.
  Notes judge_pending();

  // The newest plausible tile of each (layer, tile).
  [[nodiscard]] const std::map<FrameBuilder::TileKey, core::TileMsg>& tiles() const { return tiles_; }
  // The value of the newest tile at cell c of `layer`; NaN where no tile arrived.
  [[nodiscard]] float field_value(int layer, core::Cell c) const;

 private:
  void on_states(const std::vector<core::UavStateMsg>& states, Clock::time_point now);
  void on_broadcasts(const std::vector<core::BroadcastMsg>& broadcasts, Clock::time_point now);
  void on_departed_uavs(const std::vector<uint32_t>& gone, Clock::time_point now);
  void on_target_events(const std::vector<core::TargetEventMsg>& events);
  void on_healths(const std::vector<core::HealthMsg>& healths, Clock::time_point now);
  void on_fields(std::vector<core::FieldMsg>& fields, std::vector<core::TileMsg>& tiles, uint32_t ceiling);
  void on_tiles(std::vector<core::TileMsg>& tiles, uint32_t ceiling);
  void on_departed_places(const std::vector<uint32_t>& gone);
  void on_phase_dones(const std::vector<core::PhaseDoneMsg>& dones, Clock::time_point now);
  void note_acquisitions();
  void refuse(core::Refusal r, const std::string& what);
  void note(IntakeNote::Kind kind, IntakeNote::Level level, std::string line);

  Parts p_;
  Standby standby_;
  core::MapGeometry geo_;
  uint32_t swarm_;  // the scenario's UAVs: ids 0..swarm_-1
  int layers_;
  std::vector<core::ValueRange> layer_ranges_;  // physical range per layer (tiles out of it are refused)
  UncertaintyTracker* uncertainty_ = nullptr;
  std::map<FrameBuilder::TileKey, core::TileMsg> tiles_;
  Notes notes_;  // of the call under way
};

}  // namespace pheromesh::console
