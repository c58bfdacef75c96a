// A policy that breaks its own speed limit, for the plausibility tests
// (issue 42, docs/writing-a-policy.md "How far a UAV may fly"): every UAV
// flies along the rows of the map `step` cells a tick (bouncing at the
// edges, one row down at each bounce) and marks each cell it is over, while
// it declares `max_step` cells a tick. With the defaults (5 against 1.5)
// every state is refused by the UAV's gateway, in the simulator and in the
// processes alike. With `detour_every` N it walks `step` cells a tick and
// every N-th tick reports a position `detour` cells off its row for that
// one tick: that state is refused, the next one (back on the row) accepted.
// It never reads its view: its flight is the same whatever it is shown.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <span>
#include <string>

#include "pheromesh/core/declared_layers.hpp"
#include "pheromesh/core/policy_plugin.hpp"

namespace leaper {

using namespace pheromesh::core;

struct LeaperConfig final : PolicyConfig {
  static constexpr std::string_view kPolicy = "leaper";
  [[nodiscard]] std::string_view policy() const override { return kPolicy; }
  int32_t step = 5;         // [cell/tick] how far it flies along its row
  double max_step = 1.5;    // [cell/tick] how far it says it can fly
  uint32_t detour_every = 0;  // [tick] 0: never
  int32_t detour = 5;       // [cell] off its row, for one tick
  LayerSpec layer{"trail", 0.05, 0.1, 1000.0F};
};

int32_t whole(PluginConfig& config, const char* key, double fallback, double lo, double hi) {
  const double v = config.number_in(key, fallback, lo, hi);
  if (v != std::floor(v)) config.fail(key, "must be a whole number");
  return static_cast<int32_t>(v);
}

void parse(PluginConfig& config, ScenarioConfig& cfg) {
  LeaperConfig c;
  c.step = whole(config, "step", c.step, 0, 64);
  c.max_step = config.number_in("max_step", c.max_step, 0.1, 64.0);
  c.detour_every = static_cast<uint32_t>(whole(config, "detour_every", 0, 0, 1e6));
  c.detour = whole(config, "detour", c.detour, 1, 64);
  cfg.set_policy_config(std::move(c));
}

PolicyTraits traits(const ScenarioConfig& s) {
  const auto& c = s.config_of<LeaperConfig>();
  PolicyTraits t;
  declare_layers(t, std::span<const LayerSpec>(&c.layer, 1));
  t.sensor_radius = 1.0;
  t.view_radius = 2.0;
  t.max_step = c.max_step;
  t.deposit_reach = 0.0;  // it marks the cell it is over
  return t;
}

class LeaperUav final : public UavPolicy {
 public:
  LeaperUav(const ScenarioConfig& s, const MapGeometry& geo, uint32_t id)
      : c_(s.config_of<LeaperConfig>()), geo_(geo), track_(start_cell(s, id)), cell_(track_) {}

  void step(const UavView& view, UavActions& out) override {
    const Cell before = cell_;
    fly();
    cell_ = track_;
    if (c_.detour_every > 0 && view.tick > 0 && view.tick % c_.detour_every == 0) {
      // One tick off the row, towards the map's larger side.
      const int32_t up = track_.y - c_.detour, down = track_.y + c_.detour;
      cell_.y = down < geo_.height() ? down : std::max(up, 0);
    }
    out.deposits.push_back(layer_add(geo_, 0, cell_, 10.0));
    out.state.x = cell_.x;
    out.state.y = cell_.y;
    out.state.vx = cell_.x - before.x;
    out.state.vy = cell_.y - before.y;
    out.state.role = static_cast<uint8_t>(Role::Searcher);
  }

  [[nodiscard]] Cell cell() const override { return cell_; }

 private:
  // `step` cells along the row; at an edge it bounces back and goes one row down.
  void fly() {
    const int32_t last = geo_.width() - 1;
    int32_t x = track_.x + east_ * c_.step;
    if (x > last || x < 0) {
      x = x > last ? 2 * last - x : -x;
      x = std::clamp(x, 0, last);
      east_ = -east_;
      track_.y = (track_.y + 1) % geo_.height();
    }
    track_.x = x;
  }

  const LeaperConfig& c_;
  const MapGeometry& geo_;
  Cell track_;
  Cell cell_;
  int32_t east_ = 1;
};

std::unique_ptr<UavPolicy> make_uav(const ScenarioConfig& s, const MapGeometry& geo, const World&, uint32_t id) {
  return std::make_unique<LeaperUav>(s, geo, id);
}

std::unique_ptr<PlaceModel> make_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region) {
  return make_declared_layers_place({s.config_of<LeaperConfig>().layer}, geo, region);
}

std::map<std::string, double> field_summary(const ScenarioConfig& s, const FieldLookup& value) {
  double marked = 0.0;
  for (int32_t y = 0; y < s.height; ++y) {
    for (int32_t x = 0; x < s.width; ++x) marked += value(0, {x, y}) > 0.0F ? 1.0 : 0.0;
  }
  return {{"cells_marked", marked}};
}

const PluginPolicy kLeaper{
    .name = LeaperConfig::kPolicy,
    .summary = "UAVs fly along the rows `step` cells a tick while declaring max_step (a policy that breaks its limit)",
    .parse = &parse,
    .traits = &traits,
    .broadcasts = false,
    .make_uav = &make_uav,
    .make_place = &make_place,
    .field_summary = &field_summary,
};

}  // namespace leaper

PHEROMESH_POLICY_PLUGIN(leaper::kLeaper)
