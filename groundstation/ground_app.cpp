#include "ground_app.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>

namespace pheromesh::groundstation {

namespace {
std::vector<core::Cell> all_starts(const core::ScenarioConfig& s) {
  std::vector<core::Cell> out;
  for (uint32_t i = 0; i < s.uavs; ++i) out.push_back(core::start_cell(s, i));
  return out;
}
}  // namespace

GroundApp::GroundApp(GroundConfig cfg, core::ScenarioConfig scenario, std::unique_ptr<bus::Bus> bus)
    : cfg_(std::move(cfg)),
      scenario_(std::move(scenario)),
      geo_(scenario_.geometry()),
      world_(geo_, scenario_.obstacles, scenario_.targets),
      bus_(std::move(bus)),
      log_(spdlog::default_logger()),
      coverage_(world_, all_starts(scenario_), scenario_.aco.sensor_radius),
      acquisitions_(scenario_.targets.size()) {
  if (cfg_.expect_uavs == 0) cfg_.expect_uavs = scenario_.uavs;
}

void GroundApp::poll() {
  states_.clear();
  bus_->take_uav_states(states_);
  for (const auto& s : states_) {
    if (auto reason = core::check_uav_state(s, geo_)) {
      if (++samples_rejected_ <= 3) log_->warn("dropped state of uav {}: {}", s.uav, *reason);
      continue;
    }
    auto& u = uavs_[s.uav];
    if (!u.alive && !s.finished) log_->info("uav {} is back at tick {}", s.uav, s.tick);
    u.last = s;
    u.alive = true;
    u.finished = u.finished || s.finished;
    max_tick_ = std::max(max_tick_, s.tick);
    coverage_.observe({static_cast<int32_t>(std::lround(s.x)), static_cast<int32_t>(std::lround(s.y))});
  }
  std::vector<uint32_t> gone;
  bus_->take_departed_uavs(gone);
  for (uint32_t id : gone) {
    auto& u = uavs_[id];
    if (u.alive && !u.finished) log_->warn("uav {} lost (liveliness) at tick {}", id, u.last.tick);
    u.alive = false;
  }
  detections_.clear();
  bus_->take_detections(detections_);
  for (const auto& d : detections_) {
    if (d.target < 0 || static_cast<std::size_t>(d.target) >= scenario_.targets.size()) {
      ++samples_rejected_;
      continue;
    }
    if (acquisitions_.acquire(d.target, d.tick)) {
      log_->info("target {} at ({},{}) first acquired by uav {} at tick {} ({}/{})", d.target, d.cell.x, d.cell.y, d.uav,
                 d.tick, acquisitions_.found(), scenario_.targets.size());
    }
  }
  events_.clear();
  bus_->take_target_events(events_);
  for (const auto& e : events_) {
    if (e.kind == static_cast<uint8_t>(core::MarkEvent::Kind::Revisited)) revisit_response_.push_back(e.response_ticks);
  }
  healths_.clear();
  bus_->take_health(healths_);
  for (const auto& h : healths_) health_[h.region] = h;
  // Tiles are validated here (the web console of a later issue draws them).
  tiles_.clear();
  bus_->take_tiles(tiles_);
  for (const auto& t : tiles_) {
    if (auto reason = core::check_tile(t, geo_)) {
      if (++samples_rejected_ <= 3) log_->warn("dropped tile ({},{}): {}", t.tile.tx, t.tile.ty, *reason);
    }
  }
  std::vector<core::RegionId> regions_gone;
  bus_->take_departed_regions(regions_gone);
  for (auto r : regions_gone) {
    if (!health_[r].finished) log_->warn("place agent of region {} lost (liveliness)", r);
    region_departed_[r] = true;
  }
}

void GroundApp::print_progress() {
  uint32_t alive = 0;
  uint64_t sent = 0;
  for (const auto& [id, u] : uavs_) {
    alive += (u.alive && !u.finished) ? 1 : 0;
    sent += u.last.deposits_sent;
  }
  uint64_t applied = 0, rejected = 0;
  for (const auto& [r, h] : health_) {
    applied += h.deposits_applied;
    rejected += h.deposits_rejected;
  }
  coverage_series_.emplace_back(max_tick_, coverage_.coverage());
  log_->info("tick {:5d} | uavs {}/{} flying | places {}/{} | coverage {:5.1f}% | targets {}/{} | deposits sent {} applied {} rejected {}",
             max_tick_, alive, cfg_.expect_uavs, health_.size(), geo_.region_count(), 100.0 * coverage_.coverage(),
             acquisitions_.found(), scenario_.targets.size(), sent, applied, rejected);
}

nlohmann::json GroundApp::metrics() const {
  uint64_t sent = 0;
  for (const auto& [id, u] : uavs_) sent += u.last.deposits_sent;
  uint64_t applied = 0, rejected = 0, received = 0;
  uint32_t finished_places = 0;
  for (const auto& [r, h] : health_) {
    applied += h.deposits_applied;
    rejected += h.deposits_rejected;
    received += h.deposits_received;
    finished_places += h.finished ? 1 : 0;
  }
  nlohmann::json j;
  j["scenario"] = scenario_.name;
  j["scenario_file"] = scenario_.source_path;
  j["seed"] = scenario_.seed;
  j["dds"] = bus_->vendor();
  j["ticks"] = max_tick_;
  j["uavs"] = uavs_.size();
  j["uavs_expected"] = cfg_.expect_uavs;
  j["place_agents"] = health_.size();
  j["place_agents_finished"] = finished_places;
  j["coverage"] = coverage_.coverage();
  j["reachable_cells"] = coverage_.reachable_cells();
  j["covered_cells"] = coverage_.covered_cells();
  j["targets_total"] = scenario_.targets.size();
  j["targets_found"] = acquisitions_.found();
  j["acquisition_ticks"] = acquisitions_.acquisition_ticks();
  j["revisit_response_ticks"] = revisit_response_;
  j["deposits_sent"] = sent;
  j["deposits_received"] = received;
  j["deposits_applied"] = applied;
  j["deposits_rejected"] = rejected;
  j["samples_rejected_by_ground"] = samples_rejected_;
  // The launcher owns process accounting and overwrites these two.
  j["processes_killed"] = 0;
  j["processes_crashed"] = 0;
  nlohmann::json per_uav = nlohmann::json::object();
  uint64_t tile_samples = 0, uav_ticks = 0;
  for (const auto& [id, u] : uavs_) {
    per_uav[std::to_string(id)] = {{"last_tick", u.last.tick},
                                   {"finished", u.finished},
                                   {"deposits_sent", u.last.deposits_sent},
                                   {"tile_samples_received", u.last.tile_samples_received}};
    tile_samples += u.last.tile_samples_received;
    uav_ticks += u.last.tick;
  }
  // Neighbourhood traffic: tile samples a UAV received per tick, on average.
  j["tile_samples_per_uav_tick"] = uav_ticks > 0 ? static_cast<double>(tile_samples) / static_cast<double>(uav_ticks) : 0.0;
  j["uav_status"] = per_uav;
  nlohmann::json series = nlohmann::json::array();
  for (const auto& [t, c] : coverage_series_) series.push_back({t, c});
  j["coverage_series"] = series;
  return j;
}

int GroundApp::run() {
  bus_->subscribe_ground();
  log_->info("ground station on domain {} over {}: expecting {} uavs and {} place agents", cfg_.common.domain,
             bus_->vendor(), cfg_.expect_uavs, geo_.region_count());
  auto next_progress = std::chrono::steady_clock::now();
  while (!runtime::shutdown_requested()) {
    poll();
    if (std::chrono::steady_clock::now() >= next_progress) {
      print_progress();
      next_progress += std::chrono::milliseconds(static_cast<int64_t>(cfg_.progress_period_s * 1000));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  // Final drain: wait (bounded) for every place agent's final health so the
  // deposit accounting is complete.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  for (;;) {
    poll();
    uint32_t done = 0;
    for (const auto& [r, h] : health_) done += (h.finished || region_departed_[r]) ? 1 : 0;
    if (done >= geo_.region_count() || std::chrono::steady_clock::now() > deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  print_progress();
  std::filesystem::create_directories(cfg_.out_dir);
  const std::string path = (std::filesystem::path(cfg_.out_dir) / "metrics.json").string();
  std::ofstream out(path);
  out << metrics().dump(2) << "\n";
  if (!out) {
    log_->error("cannot write {}", path);
    return 5;
  }
  log_->info("wrote {}", path);
  return 0;
}

}  // namespace pheromesh::groundstation
