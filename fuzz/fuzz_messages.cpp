// Fuzz harness: what a process does with the samples it receives, after the
// bus has converted them — the core's semantic checks (core/messages.hpp
// check_*) and a place agent's intake (PlaceCore: deposits checked, ordered
// and applied by the scenario policy's PlaceModel, halos accepted, the layer
// update, the tiles it then publishes). One input = a policy, a region and a
// sequence of hostile samples over a few ticks, read with FuzzedDataProvider.
//
// The scenarios are the shipped small ones, one per policy, all on 2 x 2
// regions (read once from the source tree).
#include <fuzzer/FuzzedDataProvider.h>

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <optional>
#include <vector>

#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/place_core.hpp"
#include "pheromesh/core/plausibility.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"

using namespace pheromesh;

namespace {

const std::vector<core::ScenarioConfig>& scenarios() {
  static const std::vector<core::ScenarioConfig> all = [] {
    std::vector<core::ScenarioConfig> v;
    for (const char* name :
         {"small-test", "small-navigation", "liu2022-small", "shostak-small", "ravankar2016-small", "duan2009-small"}) {
      auto s = core::load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/" + name + ".textproto");
      if (!s) {
        std::fprintf(stderr, "fuzz_messages: %s\n", s.error().message.c_str());
        std::abort();
      }
      v.push_back(std::move(s.value()));
    }
    return v;
  }();
  return all;
}

// Floats as a hostile writer sends them: any bit pattern (NaN, infinities,
// denormals) or an ordinary number.
float any_float(FuzzedDataProvider& in) {
  return in.ConsumeBool() ? std::bit_cast<float>(in.ConsumeIntegral<uint32_t>())
                          : in.ConsumeFloatingPointInRange<float>(-2.0F, 2e6F);
}
double any_double(FuzzedDataProvider& in) {
  return in.ConsumeBool() ? std::bit_cast<double>(in.ConsumeIntegral<uint64_t>())
                          : in.ConsumeFloatingPointInRange<double>(-2.0, 64.0);
}
// Small values hit the map and the valid ranges; any value the edges.
int32_t any_coord(FuzzedDataProvider& in) {
  return in.ConsumeBool() ? in.ConsumeIntegralInRange<int32_t>(-2, 40) : in.ConsumeIntegral<int32_t>();
}
template <typename T>
T small_or_any(FuzzedDataProvider& in, T small_max) {
  return in.ConsumeBool() ? in.ConsumeIntegralInRange<T>(0, small_max) : in.ConsumeIntegral<T>();
}
std::vector<float> floats(FuzzedDataProvider& in, std::size_t max) {
  std::vector<float> v(in.ConsumeIntegralInRange<std::size_t>(0, max));
  for (auto& x : v) x = any_float(in);
  return v;
}

core::DepositMsg deposit(FuzzedDataProvider& in, core::RegionId region) {
  core::DepositMsg d;
  d.uav = small_or_any<uint32_t>(in, 7);
  d.seq = small_or_any<uint32_t>(in, 64);
  d.tick = small_or_any<uint32_t>(in, 64);
  d.region = in.ConsumeBool() ? region : in.ConsumeIntegral<uint32_t>();
  d.kind = small_or_any<uint8_t>(in, core::kDepositKindCount);
  d.layer = small_or_any<uint8_t>(in, 4);
  d.cell = {any_coord(in), any_coord(in)};
  d.amount = any_float(in);
  for (auto& s : d.spread) s = any_float(in);
  return d;
}

core::UavStateMsg uav_state(FuzzedDataProvider& in) {
  core::UavStateMsg s;
  s.uav = small_or_any<uint32_t>(in, 7);
  s.tick = in.ConsumeIntegral<uint32_t>();
  s.x = any_double(in);
  s.y = any_double(in);
  s.vx = any_double(in);
  s.vy = any_double(in);
  s.heading = small_or_any<uint8_t>(in, 8);
  s.role = small_or_any<uint8_t>(in, 3);
  s.view = {any_coord(in), any_coord(in)};
  s.finished = in.ConsumeBool();
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  const auto& all = scenarios();
  const core::ScenarioConfig& scenario = all[in.ConsumeIntegralInRange<std::size_t>(0, all.size() - 1)];
  const core::MapGeometry geo = scenario.geometry();
  const int layers = static_cast<int>(core::policy_traits(scenario).layers.size());
  const auto region = in.ConsumeIntegralInRange<core::RegionId>(0, geo.region_count() - 1);
  core::PlaceCore place(scenario, region);

  std::vector<core::DepositMsg> deposits;
  std::vector<core::TargetEventMsg> events;
  std::vector<std::string> rejections;
  uint32_t tick = 0;
  uint64_t sent = 0;
  // Pheromone accounting (DESIGN.md): every deposit is applied or rejected
  // with a reason, and what a place agent publishes passes its peers' checks.
  const auto end_tick = [&] {
    sent += deposits.size();
    const std::size_t before = rejections.size();
    (void)place.begin_tick(deposits, tick, events, &rejections);
    place.finish_tick();
    deposits.clear();
    const core::DepositLedger& l = place.ledger();
    if (l.received != sent || l.applied + l.rejected() != sent || rejections.size() != l.rejected() ||
        rejections.size() < before) {
      __builtin_trap();
    }
    std::vector<core::TileMsg> tiles;
    place.tiles(tick + 1, core::PlaceCore::TileSelection::All, tiles);
    for (const auto& t : tiles) {
      if (auto why = core::check_tile(t, geo, layers)) {
        std::fprintf(stderr, "fuzz_messages: a published tile fails check_tile: %s\n", why->c_str());
        __builtin_trap();
      }
    }
    tick += in.ConsumeIntegralInRange<uint32_t>(1, 3);
  };
  for (int op = 0; op < 64 && in.remaining_bytes() > 0; ++op) {
    switch (in.ConsumeIntegralInRange<int>(0, 6)) {
      case 0: {
        const core::DepositMsg d = deposit(in, region);
        (void)core::check_deposit(d, geo, in.ConsumeBool() ? region : in.ConsumeIntegral<uint32_t>(), layers);
        deposits.push_back(d);
        break;
      }
      case 1: {
        core::TileMsg t;
        t.layer = small_or_any<uint8_t>(in, 4);
        t.tile = {any_coord(in), any_coord(in)};
        t.tick = in.ConsumeIntegral<uint32_t>();
        t.region = small_or_any<uint32_t>(in, 4);
        t.width = small_or_any<uint16_t>(in, 33);
        t.height = small_or_any<uint16_t>(in, 33);
        t.values = floats(in, 1100);
        (void)core::check_tile(t, geo, layers);
        break;
      }
      case 2:
        (void)core::check_uav_state(uav_state(in), geo);
        break;
      case 3: {
        core::HaloMsg h;
        h.region = small_or_any<uint32_t>(in, 4);
        h.tick = in.ConsumeIntegral<uint32_t>();
        // Ring sizes of the 2 x 2 regions of these maps are below 64.
        h.target = floats(in, 70);
        h.obstacle = in.ConsumeBool() ? std::vector<float>(h.target.size(), 0.0F) : floats(in, 70);
        const bool ok = !core::check_halo(h, geo);
        // The intake refuses what the check refuses, and more (values out of
        // the layer's range, plausibility.hpp): never accepts what it refuses.
        if (place.accept_halo(h) && !ok) __builtin_trap();
        break;
      }
      case 4: {
        core::BroadcastMsg b;
        b.uav = in.ConsumeIntegral<uint32_t>();
        b.kind = small_or_any<uint8_t>(in, core::kBroadcastKindCount);
        b.values.resize(in.ConsumeIntegralInRange<std::size_t>(0, 70));
        for (auto& v : b.values) v = any_double(in);
        (void)core::check_broadcast(b);
        break;
      }
      case 5: {
        // The plausibility checks (plausibility.hpp) on hostile numbers.
        (void)core::check_uav_id(in.ConsumeIntegral<uint32_t>(), small_or_any<uint32_t>(in, 64));
        std::optional<uint32_t> last;
        if (in.ConsumeBool()) last = in.ConsumeIntegral<uint32_t>();
        (void)core::check_seq_reachable(in.ConsumeIntegral<uint32_t>(), last, in.ConsumeIntegral<uint32_t>());
        (void)core::check_tick_reachable(in.ConsumeIntegral<uint32_t>(),
                                         core::realtime_tick_ceiling(any_double(in), any_double(in)), "state");
        const std::vector<float> v = floats(in, 40);
        (void)core::check_values_in_range(v, {in.ConsumeFloatingPoint<float>(), in.ConsumeFloatingPoint<float>()}, "tile");
        const core::UavStateMsg a = uav_state(in), b = uav_state(in);
        (void)core::check_state_motion(a, in.ConsumeBool() ? &b : nullptr, {any_coord(in), any_coord(in)}, any_double(in),
                                       in.ConsumeBool());
        core::DetectionMsg d;
        d.uav = in.ConsumeIntegral<uint32_t>();
        d.tick = in.ConsumeIntegral<uint32_t>();
        d.target = in.ConsumeIntegral<int32_t>();
        d.cell = {any_coord(in), any_coord(in)};
        const std::vector<core::Cell> targets{{any_coord(in), any_coord(in)}, {any_coord(in), any_coord(in)}};
        (void)core::check_detection(d, targets, in.ConsumeBool() ? &a : nullptr, any_double(in), any_double(in));
        break;
      }
      default:
        // A few ticks (timers, revisits, point pheromones); each tick updates
        // the whole region, so more would cost more than it finds.
        if (tick < 8) end_tick();
        break;
    }
  }

  end_tick();
  return 0;
}
