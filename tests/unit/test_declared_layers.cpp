// Declared layers (core/declared_layers.hpp), the place model plugins use:
// deposits capped, evaporation, diffusion that keeps the total, and a map
// split into regions that gives exactly the undivided map's field.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numeric>
#include <vector>

#include "pheromesh/core/declared_layers.hpp"
#include "pheromesh/core/messages.hpp"

using namespace pheromesh::core;

namespace {

struct Field {
  MapGeometry geo;
  std::vector<std::unique_ptr<PlaceModel>> regions;
  Field(int32_t rx, int32_t ry, const std::vector<LayerSpec>& layers) : geo(23, 17, 4, rx, ry) {
    for (RegionId r = 0; r < geo.region_count(); ++r) regions.push_back(make_declared_layers_place(layers, geo, r));
  }
  std::optional<std::string> deposit(int layer, Cell c, float amount) {
    DepositMsg d = layer_add(geo, layer, c, amount);
    std::vector<TargetEventMsg> events;
    return regions[geo.region_of(c)]->apply(d, 0, events);
  }
  // One tick; `exchange_halos` false is the guard: regions that do not talk.
  void tick(bool exchange_halos = true) {
    std::vector<TargetEventMsg> events;
    std::vector<HaloRing> rings;
    for (auto& r : regions) rings.push_back(r->begin_step(0, events));
    if (exchange_halos) {
      for (RegionId a = 0; a < regions.size(); ++a) {
        for (RegionId b = 0; b < regions.size(); ++b) {
          if (a != b) regions[a]->accept_halo(geo.region_rect(b), rings[b]);
        }
      }
    }
    for (auto& r : regions) r->finish_step();
  }
  [[nodiscard]] float value(int layer, Cell c) const { return regions[geo.region_of(c)]->value(layer, c); }
  [[nodiscard]] double total(int layer) const {
    double t = 0;
    for (int32_t y = 0; y < geo.height(); ++y) {
      for (int32_t x = 0; x < geo.width(); ++x) t += value(layer, {x, y});
    }
    return t;
  }
};

const std::vector<LayerSpec> kLayers{{"a", 0.05, 0.2, 100.0F}, {"b", 0.1, 0.0, 50.0F}, {"c", 0.0, 0.3, 1000.0F}};

int differing_cells(const Field& x, const Field& y, int layers) {
  int n = 0;
  for (int l = 0; l < layers; ++l) {
    for (int32_t cy = 0; cy < x.geo.height(); ++cy) {
      for (int32_t cx = 0; cx < x.geo.width(); ++cx) n += x.value(l, {cx, cy}) != y.value(l, {cx, cy}) ? 1 : 0;
    }
  }
  return n;
}

void drive(Field& f, bool exchange_halos) {
  // Deposits on and beside the region borders (tiles of 4 cells), and corners.
  const std::vector<Cell> cells{{0, 0}, {7, 3}, {8, 4}, {11, 8}, {12, 8}, {22, 16}, {15, 7}, {16, 12}};
  for (int t = 0; t < 30; ++t) {
    for (std::size_t i = 0; i < cells.size(); ++i) {
      for (int l = 0; l < 3; ++l) EXPECT_FALSE(f.deposit(l, cells[(i + t) % cells.size()], 3.0F + static_cast<float>(l)));
    }
    f.tick(exchange_halos);
  }
}

}  // namespace

TEST(DeclaredLayers, AMapSplitIntoRegionsGivesTheUndividedMapsFieldExactly) {
  Field whole(1, 1, kLayers);
  Field split(3, 2, kLayers);
  drive(whole, true);
  drive(split, true);
  EXPECT_EQ(differing_cells(whole, split, 3), 0);
  EXPECT_GT(whole.total(0), 0.0);
}

// The guard of the test above: regions that exchange no halo do differ, so
// the test would see a border the diffusion does not cross.
TEST(DeclaredLayers, GuardRegionsWithoutHalosDiffer) {
  Field whole(1, 1, kLayers);
  Field split(3, 2, kLayers);
  drive(whole, true);
  drive(split, false);
  EXPECT_GT(differing_cells(whole, split, 3), 0);
}

TEST(DeclaredLayers, DiffusionWithoutEvaporationKeepsTheTotalAndEvaporationTakesItsShare) {
  Field f(2, 2, {{"keep", 0.0, 0.4, 1e6F}, {"fade", 0.25, 0.0, 1e6F}});
  ASSERT_FALSE(f.deposit(0, {0, 0}, 100.0F));  // a corner: 3 neighbours
  ASSERT_FALSE(f.deposit(0, {8, 8}, 100.0F));  // a region corner
  ASSERT_FALSE(f.deposit(1, {5, 5}, 64.0F));
  for (int t = 0; t < 20; ++t) f.tick();
  EXPECT_NEAR(f.total(0), 200.0, 1e-3);
  EXPECT_GT(f.value(0, {20, 15}), 0.0F);  // it spread
  EXPECT_NEAR(f.value(1, {5, 5}), 64.0 * std::pow(0.75, 20.0), 1e-5);
  EXPECT_EQ(f.value(1, {6, 5}), 0.0F);  // no diffusion
}

TEST(DeclaredLayers, DepositsAreCappedAtTheLayersMaxAndOnlyLayerAddIsTaken) {
  Field f(1, 1, {{"capped", 0.0, 0.0, 10.0F}});
  ASSERT_FALSE(f.deposit(0, {3, 3}, 8.0F));
  ASSERT_FALSE(f.deposit(0, {3, 3}, 8.0F));
  EXPECT_EQ(f.value(0, {3, 3}), 10.0F);
  DepositMsg d = layer_add(f.geo, 0, {3, 3}, 1.0);
  d.kind = static_cast<uint8_t>(DepositKind::PathVisit);
  std::vector<TargetEventMsg> events;
  const auto refused = f.regions[0]->apply(d, 0, events);
  ASSERT_TRUE(refused.has_value());
  EXPECT_NE(refused->find("only LayerAdd"), std::string::npos);
  EXPECT_TRUE(f.deposit(1, {3, 3}, 1.0F).has_value());  // no layer 1
}

TEST(DeclaredLayers, LayerSpecsOutsideTheirRangesAreRefusedNamingTheLayer) {
  EXPECT_FALSE(check_layer_specs(std::vector<LayerSpec>{}).ok());
  auto bad = check_layer_specs(std::vector<LayerSpec>{{"ok", 0.1, 0.1, 1.0F}, {"wet", 1.0, 0.0, 1.0F}});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("layer 1 ('wet'): evaporation must be in [0, 1)"), std::string::npos);
  auto three = check_layer_specs(std::vector<LayerSpec>{{"a", 0, 0.1, 1.0F}, {"b", 0, 0.1, 1.0F}, {"c", 0, 0.1, 1.0F}});
  ASSERT_FALSE(three.ok());
  EXPECT_NE(three.error().message.find("3 layers diffuse; at most 2"), std::string::npos);
  PolicyTraits t;
  declare_layers(t, kLayers);
  EXPECT_EQ(t.layers, (std::vector<std::string>{"a", "b", "c"}));
  ASSERT_EQ(t.layer_ranges.size(), 3U);
  EXPECT_EQ(t.layer_ranges[1].hi, 50.0F);
}
