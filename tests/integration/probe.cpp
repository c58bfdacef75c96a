// pheromesh-test-probe: helper process for the integration tests, speaking
// only through the bus (no vendor header here either).
//
//   discover --id I --expect N   announce itself, print "discovered N" once
//                                it sees N participants (itself included),
//                                then stay until SIGTERM (bounded).
//   hostile --region R           send malformed deposits and tiles into a
//                                running swarm; print what it sent.
//   idle --id I --regions R      a UAV's endpoints and nothing else, until
//                                SIGTERM: what discovery alone costs
//                                (bench/discovery_idle.sh).
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <thread>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/runtime/process.hpp"

using namespace pheromesh;
using Clock = std::chrono::steady_clock;

namespace {

int discover(bus::Bus& b, uint32_t id, uint32_t expect, double timeout_s) {
  // Every probe publishes a (transient-local) health record under its own id
  // and counts the distinct ids it receives.
  b.subscribe_ground();
  const auto start = Clock::now();
  const auto deadline = start + std::chrono::milliseconds(static_cast<int64_t>(timeout_s * 1000));
  std::set<uint32_t> seen;
  std::vector<core::HealthMsg> inbox;
  bool reported = false;
  // Published once: TRANSIENT_LOCAL durability delivers it to every reader
  // that matches later.
  b.publish_health({id, 0, 0.0F, 0, 0, 0, 0, false});
  while (!runtime::shutdown_requested() && Clock::now() < deadline) {
    inbox.clear();
    b.take_health(inbox);
    for (const auto& h : inbox) seen.insert(h.region);
    if (!reported && seen.size() >= expect) {
      const double s = std::chrono::duration<double>(Clock::now() - start).count();
      std::printf("discovered %zu in %.2f s\n", seen.size(), s);
      std::fflush(stdout);
      reported = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  if (!reported) {
    std::printf("timeout: discovered %zu of %u\n", seen.size(), expect);
    std::fflush(stdout);
    return 1;
  }
  return 0;
}

int hostile(bus::Bus& b, uint32_t region, uint32_t map_width) {
  const auto deadline = Clock::now() + std::chrono::seconds(20);
  while (b.matched_deposit_readers(region) == 0) {
    if (Clock::now() > deadline || runtime::shutdown_requested()) {
      std::printf("no place agent for region %u\n", region);
      return 1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const uint32_t uav = 900000;  // not a UAV of the swarm
  int sent = 0;
  auto deposit = [&](uint32_t seq, uint8_t kind, core::Cell c, float amount, core::RegionId r) {
    sent += b.publish_deposit({uav, seq, 1, r, kind, 0, c, amount, {}}, r) ? 1 : 0;
  };
  deposit(1, 0, {1, 1}, std::numeric_limits<float>::quiet_NaN(), region);     // NaN amount
  deposit(2, 0, {static_cast<int32_t>(map_width) + 7, 3}, 1.0F, region);      // cell outside the map
  deposit(3, 9, {1, 1}, 1.0F, region);                                        // unknown kind
  deposit(5, 0, {1, 1}, -std::numeric_limits<float>::infinity(), region);     // negative infinity
  deposit(6, 0, {1, 1}, 1.0F, region);                                        // a valid one ...
  deposit(6, 0, {1, 1}, 1.0F, region);                                        // ... replayed
  // Tiles: declared 2 x 2 but 9 values; a tile outside the map; NaN values.
  // Each on an instance (layer, tx, ty) no place agent writes, so a place
  // agent's next tile cannot replace it in a KEEP_LAST(1) reader before it is
  // read.
  int tiles = 0;
  tiles += b.publish_tile({200, {0, 0}, 1, region, 2, 2, std::vector<float>(9, 1.0F)}) ? 1 : 0;
  tiles += b.publish_tile({0, {4000, 4000}, 1, region, 1, 1, {1.0F}}) ? 1 : 0;
  tiles += b.publish_tile({201, {0, 0}, 1, region, 1, 1, {std::numeric_limits<float>::quiet_NaN()}}) ? 1 : 0;
  // Over the IDL bound: the bus must refuse to write it.
  const bool oversized_written = b.publish_tile({0, {0, 1}, 1, region, 40, 40, std::vector<float>(1600, 0.0F)});
  b.flush(std::chrono::seconds(5));
  std::printf("hostile deposits %d valid 1 tiles %d oversized_written %d refused %llu\n", sent, tiles,
              oversized_written ? 1 : 0, static_cast<unsigned long long>(b.stats().writes_refused));
  std::fflush(stdout);
  // Acknowledged samples are in the readers' caches, but deleting our writers
  // at exit disposes their instances, which can replace a sample the ground
  // station has not taken yet (it polls every 20 ms). Stay a moment.
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  return 0;
}

int idle(bus::Bus& b, uint32_t id, uint32_t regions) {
  // Exactly the endpoints a realtime UAV creates (UavApp::run), no samples.
  b.join_uav(id, core::home_region(id, regions));
  b.subscribe_broadcasts();
  b.subscribe_commands();
  std::vector<core::ViewMsg> views;
  std::vector<core::CommandMsg> commands;
  while (!runtime::shutdown_requested()) {
    b.wait({bus::TopicKind::View, bus::TopicKind::Command}, Clock::now() + std::chrono::milliseconds(200));
    views.clear();
    commands.clear();
    b.take_views(views);
    b.take_commands(commands);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pheromesh integration-test probe", "pheromesh-test-probe"};
  app.require_subcommand(1);
  std::string dds = bus::default_vendor(), profile = "onehost";
  uint32_t domain = 0;
  app.add_option("--dds", dds);
  app.add_option("--dds-profile", profile);
  app.add_option("--domain", domain);
  uint32_t id = 0, expect = 0, region = 0, width = 30;
  double timeout_s = 120;
  auto* d = app.add_subcommand("discover", "announce and count participants");
  d->add_option("--id", id)->required();
  d->add_option("--expect", expect)->required();
  d->add_option("--timeout", timeout_s);
  uint32_t regions = 16;
  auto* i = app.add_subcommand("idle", "a UAV's endpoints, no samples, until SIGTERM");
  i->add_option("--id", id)->required();
  i->add_option("--regions", regions);
  auto* h = app.add_subcommand("hostile", "send malformed samples");
  h->add_option("--region", region);
  h->add_option("--map-width", width);
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::warn);
  runtime::install_shutdown_handlers();
  bus::BusOptions o;
  o.process_name = "probe";
  o.domain = domain;
  o.profile = profile;
  // Under PHEROMESH_DDS=mixed the probes alternate vendors by id.
  if (dds == "mixed") dds = id % 2 == 0 ? "cyclone" : "fastdds";
  auto b = bus::make_bus(dds, o);
  if (!b) {
    std::fprintf(stderr, "%s\n", b.error().message.c_str());
    return 3;
  }
  if (d->parsed()) return discover(*b.value(), id, expect, timeout_s);
  if (i->parsed()) return idle(*b.value(), id, regions);
  return hostile(*b.value(), region, width);
}
