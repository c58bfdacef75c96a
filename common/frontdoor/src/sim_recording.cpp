#include "pheromesh/frontdoor/sim_recording.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "pheromesh/core/policy.hpp"

namespace pheromesh::frontdoor {

namespace {

console::ConsoleInfo sim_console_info(const core::Simulator& sim) {
  console::ConsoleInfo info = console::console_info_of(sim.scenario());
  info.clock = "lockstep";
  info.dds = "none (in-process simulator)";
  return info;
}

core::Cell cell_of(double x, double y) {
  return {static_cast<int32_t>(std::lround(x)), static_cast<int32_t>(std::lround(y))};
}

}  // namespace

SimRecording::SimRecording(const core::Simulator& sim, console::ConsoleInfo info)
    : sim_(sim),
      info_(std::move(info)),
      state_(console::initial_state(info_)),
      builder_(sim.scenario().geometry()),
      // The live console's time constant: a tenth of the run (ground_console.cpp).
      uncertainty_(sim.scenario().geometry(), sim.world().reachable_from(core::all_starts(sim.scenario())),
                   info_.sensor_radius, std::max(1.0, sim.scenario().ticks / 10.0)) {}

core::Result<std::unique_ptr<SimRecording>> SimRecording::open(const std::string& path, const core::Simulator& sim) {
  std::unique_ptr<SimRecording> r(new SimRecording(sim, sim_console_info(sim)));
  auto w = console::RecordingWriter::open(path, r->info_);
  if (!w) return w.error();
  r->writer_ = std::move(w).value();
  return core::Result<std::unique_ptr<SimRecording>>(std::move(r));
}

bool SimRecording::after_tick(uint32_t tick) { return write_frame(tick); }

bool SimRecording::write_frame(uint32_t tick) {
  using Clock = console::FrameBuilder::Clock;
  const double t_s = tick / sim_.scenario().tick_rate_hz;
  // Liveness thresholds are in console time: simulated time here.
  const Clock::time_point now{std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(t_s))};
  const core::RunRecorder& rec = sim_.recorder();
  for (const auto& [id, u] : rec.uavs()) {
    if (u.last.tick != tick) continue;  // killed: not heard from now on
    builder_.heard_uav(id, now);
    uncertainty_.observe(cell_of(u.last.x, u.last.y), tick);
  }
  for (const auto& [region, h] : rec.health()) {
    if (h.tick == tick) builder_.heard_region(region, now);
  }
  tiles_.clear();
  for (const auto& [tile, layers] : sim_.tiles()) {
    for (const core::TileMsg& m : layers) tiles_[{m.layer, tile}] = m;
  }
  const std::vector<core::Rect> no_popups;
  const console::FrameBuilder::Sources sources{tiles_, rec, sim_.world(), sim_.scenario().targets.size(),
                                               sim_.scenario().obstacles, no_popups, false};
  console::Frame f = builder_.build(state_, sources, now, t_s);
  // A plot point per simulated second, and the last tick's.
  const auto every = static_cast<uint32_t>(std::max(1.0, std::round(sim_.scenario().tick_rate_hz)));
  if ((tick % every == 0 || tick == sim_.scenario().ticks) && last_series_tick_ != tick) {
    last_series_tick_ = tick;
    f.series = console::SeriesPoint{0,
                                    f.t_s,
                                    f.tick,
                                    rec.coverage().coverage(),
                                    static_cast<uint32_t>(rec.acquisitions().found()),
                                    uncertainty_.mean(tick)};
  }
  console::apply(state_, f);
  ++frames_;
  return writer_->write(f);
}

core::Result<uint64_t> SimRecording::close() {
  // run() has recorded the closing states and healths (finished) after the
  // last tick: one more frame shows them.
  if (!write_frame(sim_.scenario().ticks)) return core::Error{"cannot write to the recording " + writer_->path()};
  return writer_->close();
}

}  // namespace pheromesh::frontdoor
