// `pheromesh sim --record FILE`: the simulated run as a console recording
// (docs/recording.md) that `pheromesh replay` serves like one of `run
// --http`. The frames come from the console's own FrameBuilder, fed with the
// simulator's recorder and tiles after every tick; the time of a frame is the
// simulated time (tick / tick rate), not the wall time the simulation took.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "pheromesh/console/frame_builder.hpp"
#include "pheromesh/console/recording.hpp"
#include "pheromesh/console/uncertainty.hpp"
#include "pheromesh/core/result.hpp"
#include "pheromesh/core/simulator.hpp"

namespace pheromesh::frontdoor {

class SimRecording {
 public:
  // Opens `path` for the run `sim` is about to make.
  static core::Result<std::unique_ptr<SimRecording>> open(const std::string& path, const core::Simulator& sim);

  // One frame after tick `tick` of the simulation; false on an I/O error.
  bool after_tick(uint32_t tick);
  // The last frame (the final state) and the file under its name; the bytes
  // written, or why it failed.
  core::Result<uint64_t> close();
  [[nodiscard]] uint64_t frames() const { return frames_; }

 private:
  SimRecording(const core::Simulator& sim, console::ConsoleInfo info);
  bool write_frame(uint32_t tick);

  const core::Simulator& sim_;
  console::ConsoleInfo info_;
  console::ConsoleState state_;
  console::FrameBuilder builder_;
  console::UncertaintyTracker uncertainty_;
  std::unique_ptr<console::RecordingWriter> writer_;
  std::map<console::FrameBuilder::TileKey, core::TileMsg> tiles_;
  uint64_t frames_ = 0;
  std::optional<uint32_t> last_series_tick_;
};

}  // namespace pheromesh::frontdoor
