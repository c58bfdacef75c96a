// Repulsive coverage: a policy none of pheromesh's papers has, as a plugin.
//
// Every UAV marks the cell it is over with a repulsive pheromone and steps to
// the neighbouring cell that holds the least of it, so the swarm spreads over
// the map and keeps away from where it (or another UAV) has just been. The
// mark evaporates and diffuses, so an old trail fades and a fresh one repels
// a little around itself. Deterministic: no random numbers, ties broken by a
// fixed order, so a lockstep run gives the simulator's numbers.
//
// What a plugin is made of (docs/writing-a-policy.md):
//   1. a config struct (RepulsiveConfig) and a parser that reads it from the
//      scenario's `config` parameters, reporting errors at their lines;
//   2. the traits: its layers (name, evaporation, diffusion, range);
//   3. a UavPolicy (what one UAV does each tick) and a PlaceModel (here the
//      declared layers of pheromesh, no code of our own);
//   4. a PluginPolicy naming them, exported with PHEROMESH_POLICY_PLUGIN.
#include <pheromesh/core/declared_layers.hpp>
#include <pheromesh/core/heading.hpp>
#include <pheromesh/core/policy_plugin.hpp>

#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <stdexcept>
#include <memory>
#include <string>
#include <vector>

namespace repulsive {

using namespace pheromesh::core;

// 1. The config ------------------------------------------------------------
struct RepulsiveConfig final : PolicyConfig {
  static constexpr std::string_view kPolicy = "repulsive_coverage";
  [[nodiscard]] std::string_view policy() const override { return kPolicy; }

  double mark = 10.0;          // pheromone a UAV leaves on its cell each tick
  double sensor_radius = 2.0;  // [cell] targets within this are found
  LayerSpec layer{"repulsion", 0.01, 0.1, 1000.0F};
  // "stay" (default): a UAV whose every neighbour is blocked stays put;
  // "error": such a UAV throws, which stops its process (to show how a
  // plugin's exception is reported: docs/writing-a-policy.md).
  bool throw_when_blocked = false;
  // A tick at which every UAV throws (0: never), for the same demonstration.
  uint32_t fail_at_tick = 0;
};

void parse(PluginConfig& config, ScenarioConfig& cfg) {
  RepulsiveConfig c;
  c.mark = config.number_in("mark", c.mark, 0.0, 1e6);
  c.sensor_radius = config.number_in("sensor_radius", c.sensor_radius, 0.0, 64.0);
  c.layer.evaporation = config.number_in("evaporation", c.layer.evaporation, 0.0, 0.999);
  c.layer.diffusion = config.number_in("diffusion", c.layer.diffusion, 0.0, 0.999);
  c.layer.max = static_cast<float>(config.number_in("max", c.layer.max, 1e-3, 1e6));
  if (c.mark > c.layer.max) {
    config.fail("mark", "must not exceed max (" + std::to_string(c.layer.max) + "): a cell holds at most max");
  }
  if (const auto when = config.text("when_blocked")) {
    if (*when == "error") {
      c.throw_when_blocked = true;
    } else if (*when != "stay") {
      config.fail("when_blocked", "must be \"stay\" or \"error\" (got \"" + *when + "\")");
    }
  }
  const double fail_at = config.number_in("fail_at_tick", 0.0, 0.0, 1e9);
  if (fail_at != std::floor(fail_at)) config.fail("fail_at_tick", "must be a whole tick");
  c.fail_at_tick = static_cast<uint32_t>(fail_at);
  cfg.set_policy_config(std::move(c));
}

// 2. The traits ------------------------------------------------------------
PolicyTraits traits(const ScenarioConfig& s) {
  const auto& c = s.config_of<RepulsiveConfig>();
  PolicyTraits t;
  declare_layers(t, std::span<const LayerSpec>(&c.layer, 1));
  t.sensor_radius = c.sensor_radius;
  t.view_radius = 2.0;  // the 8 neighbours, with a margin
  t.max_step = 1.5;     // one cell, diagonals included (sqrt 2)
  t.reads_neighbours = false;  // it steers by the layer alone: its views carry no other UAVs
  t.deposit_reach = 0.0;  // it marks the cell it is over: a place agent refuses a mark anywhere else
  return t;
}

// 3. The UAV ---------------------------------------------------------------
class RepulsiveUav final : public UavPolicy {
 public:
  RepulsiveUav(const ScenarioConfig& s, const MapGeometry& geo, const World& world, uint32_t id)
      : c_(s.config_of<RepulsiveConfig>()), geo_(geo), world_(world), id_(id), cell_(start_cell(s, id)) {}

  void step(const UavView& view, UavActions& out) override {
    if (c_.fail_at_tick != 0 && view.tick == c_.fail_at_tick) {
      throw std::runtime_error("repulsive_coverage: uav " + std::to_string(id_) + " was told to fail at tick " +
                               std::to_string(view.tick) + " (config fail_at_tick)");
    }
    const Cell before = cell_;
    if (view.tick > 0) move(view);
    // Mark where we are, and report the targets in sensor range.
    out.deposits.push_back(layer_add(geo_, 0, cell_, c_.mark));
    for (const int32_t t : world_.sense(cell_, c_.sensor_radius).targets) {
      DetectionMsg d;
      d.target = t;
      d.cell = world_.targets()[static_cast<std::size_t>(t)];
      out.detections.push_back(d);
    }
    out.state.x = cell_.x;
    out.state.y = cell_.y;
    out.state.vx = cell_.x - before.x;
    out.state.vy = cell_.y - before.y;
    out.state.heading = static_cast<uint8_t>(heading_);
    out.state.role = static_cast<uint8_t>(Role::Searcher);
  }

  [[nodiscard]] Cell cell() const override { return cell_; }

 private:
  // The follow rule: the free neighbour with the least repulsion; ties go to
  // straight on, then to the lowest heading number. A neighbour whose tile
  // has not arrived is not a candidate.
  void move(const UavView& view) {
    float best = std::numeric_limits<float>::infinity();
    int best_turn = -1;
    for (int turn = 0; turn < 8; ++turn) {
      const Heading h = rotate(heading_, turn);
      const Cell d = step_of(h);
      const Cell n{cell_.x + d.x, cell_.y + d.y};
      if (!geo_.in_map(n) || world_.is_obstacle(n)) continue;
      const std::optional<float> v = view.tiles->value(0, n);
      if (!v) continue;
      // Straight on (turn 0) first; then by heading number.
      const bool better = *v < best || (*v == best && best_turn != 0 &&
                                         static_cast<int>(h) < static_cast<int>(rotate(heading_, best_turn)));
      if (better) {
        best = *v;
        best_turn = turn;
      }
    }
    if (best_turn < 0) {
      if (c_.throw_when_blocked) {
        throw std::runtime_error("repulsive_coverage: uav " + std::to_string(id_) + " at (" + std::to_string(cell_.x) +
                                 ", " + std::to_string(cell_.y) + ") has no free neighbour it can read");
      }
      return;
    }
    heading_ = rotate(heading_, best_turn);
    const Cell d = step_of(heading_);
    cell_ = {cell_.x + d.x, cell_.y + d.y};
  }

  const RepulsiveConfig& c_;
  const MapGeometry& geo_;
  const World& world_;
  uint32_t id_;
  Cell cell_;
  Heading heading_ = Heading::E;
};

std::unique_ptr<UavPolicy> make_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& world, uint32_t id) {
  return std::make_unique<RepulsiveUav>(s, geo, world, id);
}

// The place agents keep the declared layer: LayerAdd deposits, evaporation
// and diffusion across region borders, all pheromesh's.
std::unique_ptr<PlaceModel> make_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region) {
  return make_declared_layers_place({s.config_of<RepulsiveConfig>().layer}, geo, region);
}

// The final field's numbers for metrics.json "field".
std::map<std::string, double> field_summary(const ScenarioConfig& s, const FieldLookup& value) {
  double total = 0.0;
  double marked = 0.0;
  for (int32_t y = 0; y < s.height; ++y) {
    for (int32_t x = 0; x < s.width; ++x) {
      const double v = value(0, {x, y});
      total += v;
      marked += v > 0.0 ? 1.0 : 0.0;
    }
  }
  return {{"repulsion_total", total}, {"cells_marked", marked}};
}

// 4. The entry -------------------------------------------------------------
const PluginPolicy kRepulsiveCoverage{
    .name = RepulsiveConfig::kPolicy,
    .summary = "UAVs mark their cell with a repulsive pheromone and step to the neighbour holding the least",
    .parse = &parse,
    .traits = &traits,
    .broadcasts = false,
    .make_uav = &make_uav,
    .make_place = &make_place,
    .field_summary = &field_summary,
};

}  // namespace repulsive

PHEROMESH_POLICY_PLUGIN(repulsive::kRepulsiveCoverage)
