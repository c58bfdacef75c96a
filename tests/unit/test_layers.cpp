// Shao 2020 pheromone layers: hand-worked steps of Shao 2020 eq. (1), Shao 2020 eq. (2), Shao 2020 eq. (3), Shao 2020 eq. (4), Shao 2020 eq. (5), Shao 2020 eq. (6), Shao 2020 eq. (7), Shao 2020 eq. (8), the halo
// protocol, and the split-map == undivided-map invariant.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/place_core.hpp"
#include "pheromesh/core/rng.hpp"

namespace pheromesh::core {
namespace {

constexpr float kTol = 1e-6F;

std::size_t local(const Rect& r, Cell c) {
  return static_cast<std::size_t>(c.y - r.y0) * static_cast<std::size_t>(r.w) + static_cast<std::size_t>(c.x - r.x0);
}

void step(RegionField& f) {
  (void)f.begin_step();
  f.finish_step();
}

// Copy the target and obstacle layers of a whole-map field into flat vectors.
std::vector<float> whole(const RegionField& f, Layer l) {
  const auto v = f.layer(l);
  return {v.begin(), v.end()};
}

// ---------------------------------------------------------------------------
// Target and obstacle: Shao 2020 eq. (1), Shao 2020 eq. (2), Shao 2020 eq. (3), Shao 2020 eq. (4)
// ---------------------------------------------------------------------------

TEST(Layers, StartEmptyExceptPathAtSigmaZero) {
  const MapGeometry g(6, 4, 3, 2, 1);
  const RegionField f(g, 1, ShaoLayerParams{});
  EXPECT_EQ(f.rect(), (Rect{3, 0, 3, 4}));
  for (const float v : f.layer(Layer::Target)) EXPECT_EQ(v, 0.0F);
  for (const float v : f.layer(Layer::Obstacle)) EXPECT_EQ(v, 0.0F);
  for (const float v : f.layer(Layer::TargetState)) EXPECT_EQ(v, kTargetUnknown);
  for (const float v : f.layer(Layer::Path)) EXPECT_EQ(v, 2.0F);  // σ0 = 2
}

TEST(Layers, EvaporationAloneScalesBySurvivingFraction) {
  const MapGeometry g(3, 3, 3, 1, 1);
  ShaoLayerParams p;
  p.g_tau = 0.0;  // no diffusion: g(i,t) = 0 and (1-G) = 1
  p.g_eps = 0.0;
  p.e_tau = 0.2;
  p.e_eps = 0.5;
  p.d_tau = 1.0;
  p.d_eps = 1.0;
  RegionField f(g, 0, p);
  auto tau = f.mutable_layer(Layer::Target);
  auto eps = f.mutable_layer(Layer::Obstacle);
  tau[0] = 1.0F;  // (0,0), switch off
  tau[4] = 0.5F;  // (1,1), switch on
  f.set_target_switch({1, 1}, true);
  eps[0] = 1.0F;   // (0,0)
  eps[8] = 0.25F;  // (2,2), switch on
  f.set_obstacle_switch({2, 2});

  step(f);
  // Shao 2020 eq. (1): τ = (1-0.2)·1·[τ + k·1]:  (0,0) 0.8·1 = 0.8;  (1,1) 0.8·1.5 = 1.2
  EXPECT_NEAR(f.value(Layer::Target, {0, 0}), 0.8F, kTol);
  EXPECT_NEAR(f.value(Layer::Target, {1, 1}), 1.2F, kTol);
  EXPECT_EQ(f.value(Layer::Target, {2, 2}), 0.0F);
  // Shao 2020 eq. (3): ε = (1-0.5)·{1·[ε + k·1] + 0}:  (0,0) 0.5;  (2,2) 0.5·1.25 = 0.625
  EXPECT_NEAR(f.value(Layer::Obstacle, {0, 0}), 0.5F, kTol);
  EXPECT_NEAR(f.value(Layer::Obstacle, {2, 2}), 0.625F, kTol);

  step(f);
  // (0,0): 0.8·0.8 = 0.64;  (1,1): 0.8·(1.2 + 1) = 1.76
  EXPECT_NEAR(f.value(Layer::Target, {0, 0}), 0.64F, kTol);
  EXPECT_NEAR(f.value(Layer::Target, {1, 1}), 1.76F, kTol);
  // (2,2): 0.5·(0.625 + 1) = 0.8125
  EXPECT_NEAR(f.value(Layer::Obstacle, {2, 2}), 0.8125F, kTol);
}

// 3x3 map: |N| = 3 at the corners, 5 on the edges, 8 at the centre.
// E = 0.25, G = 0.4, d = 1; k = 1 at (0,0) only, v(1,0) = 0.5, all else 0.
// Sources s = v + k·d: s(0,0) = 1, s(1,0) = 0.5, others 0.
// Neighbour sums Σ_{j∈N(i)} s_j/|N(j)| (only (0,0) with |N| = 3 and (1,0)
// with |N| = 5 contribute):
//   (0,0): s(1,0)/5 = 0.1            (1,0): s(0,0)/3 = 0.3333
//   (2,0): s(1,0)/5 = 0.1            (0,1): 1/3 + 0.5/5 = 0.4333
//   (1,1): 1/3 + 0.5/5 = 0.4333      (2,1): 0.5/5 = 0.1     row 2: 0
ShaoLayerParams hand_params() {
  ShaoLayerParams p;
  p.e_tau = 0.25;
  p.g_tau = 0.4;
  p.d_tau = 1.0;
  p.e_eps = 0.25;
  p.g_eps = 0.4;
  p.d_eps = 1.0;
  return p;
}

TEST(Layers, TargetSourceDiffusesByNeighbourCountsOfTheSenders) {
  const MapGeometry g(3, 3, 3, 1, 1);
  const ShaoLayerParams p = hand_params();
  RegionField f(g, 0, p);
  f.set_target_switch({0, 0}, true);
  f.mutable_layer(Layer::Target)[1] = 0.5F;  // (1,0)
  const std::vector<float> before = whole(f, Layer::Target);
  step(f);
  // Shao 2020 eq. (1): τ = (1-E)(1-G)·s + G·Σ = 0.45·s + 0.4·Σ
  const float expected[9] = {
      0.49F,       // 0.45·1   + 0.4·0.1    = 0.45 + 0.04
      0.358333F,   // 0.45·0.5 + 0.4·0.3333 = 0.225 + 0.13333
      0.04F,       // 0.4·0.1
      0.173333F,   // 0.4·0.4333
      0.173333F,   // 0.4·0.4333
      0.04F,       // 0.4·0.1
      0.0F, 0.0F, 0.0F};
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(f.layer(Layer::Target)[static_cast<std::size_t>(i)], expected[i], kTol) << i;

  // The reference gives the same numbers.
  std::vector<uint8_t> k(9, 0);
  k[0] = 1;
  std::vector<float> out(9, -1.0F);
  reference_diffuse(g, before, k, p.e_tau, p.g_tau, p.d_tau, false, out);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(out[static_cast<std::size_t>(i)], expected[i], kTol) << i;
}

TEST(Layers, ObstacleEvaporationAlsoMultipliesTheNeighbourSum) {
  const MapGeometry g(3, 3, 3, 1, 1);
  const ShaoLayerParams p = hand_params();
  RegionField f(g, 0, p);
  f.set_obstacle_switch({0, 0});
  f.mutable_layer(Layer::Obstacle)[1] = 0.5F;  // (1,0)
  const std::vector<float> before = whole(f, Layer::Obstacle);
  step(f);
  // Shao 2020 eq. (3): ε = (1-E)·{(1-G)·s + G·Σ} = 0.75·(0.6·s + 0.4·Σ)
  const float expected[9] = {
      0.48F,   // 0.75·(0.6 + 0.04)          = 0.75·0.64
      0.325F,  // 0.75·(0.3 + 0.13333)       = 0.75·0.43333
      0.03F,   // 0.75·0.04
      0.13F,   // 0.75·0.4·0.4333 = 0.75·0.17333
      0.13F,   //
      0.03F,   // 0.75·0.04
      0.0F, 0.0F, 0.0F};
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(f.layer(Layer::Obstacle)[static_cast<std::size_t>(i)], expected[i], kTol) << i;

  std::vector<uint8_t> k(9, 0);
  k[0] = 1;
  std::vector<float> out(9, -1.0F);
  reference_diffuse(g, before, k, p.e_eps, p.g_eps, p.d_eps, true, out);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(out[static_cast<std::size_t>(i)], expected[i], kTol) << i;
}

TEST(Layers, DiffusionWithoutEvaporationConservesMass) {
  // With E = 0, Σ_i out_i = (1-G)Σ s + G Σ_j s_j·|N(j)|/|N(j)| = Σ s: every
  // cell hands out exactly G·s_j, split over its in-map neighbours.
  const MapGeometry g(7, 5, 5, 1, 1);
  ShaoLayerParams p;
  p.e_tau = 0.0;
  p.g_tau = 0.3;
  p.d_tau = 1.0;
  RegionField f(g, 0, p);
  Rng rng(11);
  double mass = 0.0;
  for (float& v : f.mutable_layer(Layer::Target)) {
    v = static_cast<float>(rng.uniform01());
    mass += v;
  }
  f.set_target_switch({0, 0}, true);
  f.set_target_switch({3, 2}, true);
  mass += 2.0;  // two deposits of d = 1
  step(f);
  double after = 0.0;
  for (const float v : f.layer(Layer::Target)) after += v;
  EXPECT_NEAR(after, mass, 1e-4);
}

TEST(Layers, SwitchesAreKeptPerCellAndIgnoredOutsideTheRegion) {
  const MapGeometry g(20, 10, 5, 2, 1);
  RegionField f(g, 0, ShaoLayerParams{});  // cells x in [0,10)
  f.set_target_switch({3, 3}, true);
  f.set_obstacle_switch({4, 4});
  f.set_target_switch({15, 3}, true);  // region 1: ignored
  f.set_obstacle_switch({-1, 3});      // off the map: ignored
  EXPECT_TRUE(f.target_switch({3, 3}));
  EXPECT_TRUE(f.obstacle_switch({4, 4}));
  EXPECT_FALSE(f.target_switch({4, 4}));
  EXPECT_FALSE(f.target_switch({15, 3}));
  EXPECT_FALSE(f.obstacle_switch({-1, 3}));
  f.set_target_switch({3, 3}, false);
  EXPECT_FALSE(f.target_switch({3, 3}));
}

TEST(Layers, TargetStateIsStoredAndNotUpdatedByStep) {
  const MapGeometry g(10, 10, 5, 1, 1);
  RegionField f(g, 0, ShaoLayerParams{});
  f.set_target_state({2, 3}, kTargetDue);
  f.set_target_state({5, 5}, kTargetMarked);
  f.set_target_state({50, 5}, kTargetDue);  // outside: ignored
  for (int i = 0; i < 5; ++i) step(f);
  EXPECT_EQ(f.value(Layer::TargetState, {2, 3}), kTargetDue);
  EXPECT_EQ(f.value(Layer::TargetState, {5, 5}), kTargetMarked);
  EXPECT_EQ(f.value(Layer::TargetState, {0, 0}), kTargetUnknown);
}

TEST(Layers, NamesAreStable) {
  EXPECT_EQ(std::string_view(layer_name(Layer::Target)), "target");
  EXPECT_EQ(std::string_view(layer_name(Layer::Obstacle)), "obstacle");
  EXPECT_EQ(std::string_view(layer_name(Layer::Path)), "path");
  EXPECT_EQ(std::string_view(layer_name(Layer::TargetState)), "target_state");
}

// ---------------------------------------------------------------------------
// Path: Shao 2020 eq. (5), Shao 2020 eq. (6), Shao 2020 eq. (7), Shao 2020 eq. (8)
// ---------------------------------------------------------------------------

// 1/(2·sqrt(2π)) = 0.19947114020071635; with σ0 = 2, Q = 1, D0 = 4.
TEST(Path, DecreaseFollowsEquationSeven) {
  const ShaoLayerParams p;
  EXPECT_DOUBLE_EQ(path_decrease(0.0, p), 1.8);  // 0.9·σ0
  // D = 1: 0.19947114·exp(-(1/1)²/2)·2 = 0.19947114·0.60653066·2
  EXPECT_NEAR(path_decrease(1.0, p), 0.24197072451914337, 1e-12);
  // D = 2: 0.19947114·exp(-(1/2)²/2 = -0.125)·2 = 0.19947114·0.88249690·2
  EXPECT_NEAR(path_decrease(2.0, p), 0.3520653267642995, 1e-12);
  // D = 4 = D0 (still inside): exp(-(1/4)²/2 = -1/32) = 0.96923323
  EXPECT_NEAR(path_decrease(4.0, p), 0.38666811680284924, 1e-12);
  EXPECT_EQ(path_decrease(4.5, p), 0.0);  // D > D0
}

TEST(Path, StaysWithinSigmaMinAndSigmaZero) {
  const MapGeometry g(3, 3, 3, 1, 1);
  RegionField f(g, 0, ShaoLayerParams{});
  f.add_path_visit({1, 1});
  step(f);
  EXPECT_NEAR(f.value(Layer::Path, {1, 1}), 0.2F, kTol);  // 2 - 1.8
  f.add_path_visit({1, 1});
  step(f);
  EXPECT_EQ(f.value(Layer::Path, {1, 1}), 0.1F);  // 0.2 - 1.8 < σmin = 0.1
  f.mutable_layer(Layer::Path)[0] = 3.0F;         // above σ0
  step(f);
  EXPECT_EQ(f.value(Layer::Path, {0, 0}), 2.0F);  // clamped to σ0
  EXPECT_EQ(f.value(Layer::Path, {1, 1}), 0.1F);  // not diffused, not evaporated
}

TEST(Path, TwoUavsDecreasingTheSameCellAdd) {
  const MapGeometry g(9, 9, 9, 1, 1);
  RegionField f(g, 0, ShaoLayerParams{});
  f.add_path_visit({2, 4});
  f.add_path_visit({6, 4});
  step(f);
  // (4,4): D = 2 from both: 2 - 2·0.35206533 = 1.29586935
  EXPECT_NEAR(f.value(Layer::Path, {4, 4}), 1.29586935F, kTol);
  // (3,4): D = 1 and 3: 2 - (0.24197072 + 0.37738323) = 1.38064605
  EXPECT_NEAR(f.value(Layer::Path, {3, 4}), 1.38064605F, kTol);
  // (0,0): D = sqrt(4+16) = 4.47 and sqrt(36+16) = 7.2: both beyond D0
  EXPECT_EQ(f.value(Layer::Path, {0, 0}), 2.0F);
}

TEST(Path, UavJustOutsideTheRegionDecreasesCellsInside) {
  const MapGeometry g(20, 10, 5, 2, 1);  // region 0: x in [0,10)
  RegionField f(g, 0, ShaoLayerParams{});
  f.add_path_visit({10, 5});  // in region 1
  step(f);
  EXPECT_NEAR(f.value(Layer::Path, {9, 5}), 2.0F - 0.24197072F, kTol);  // D = 1
  EXPECT_NEAR(f.value(Layer::Path, {6, 5}), 2.0F - 0.38666812F, kTol);  // D = 4 = D0
  EXPECT_EQ(f.value(Layer::Path, {5, 5}), 2.0F);                        // D = 5
  EXPECT_EQ(f.value(Layer::Path, {9, 1}), 2.0F);                        // D = sqrt(17) > 4
  // A UAV far away changes nothing.
  f.add_path_visit({19, 0});
  step(f);
  EXPECT_NEAR(f.value(Layer::Path, {9, 5}), 2.0F - 0.24197072F, kTol);
}

// ---------------------------------------------------------------------------
// Halo ring protocol
// ---------------------------------------------------------------------------

TEST(Halo, RingSizeCountsBorderCells) {
  EXPECT_EQ(ring_size({0, 0, 4, 3}), 10U);  // 2·4 + 2·3 - 4
  EXPECT_EQ(ring_size({5, 5, 3, 3}), 8U);
  EXPECT_EQ(ring_size({0, 0, 2, 2}), 4U);
  EXPECT_EQ(ring_size({0, 0, 1, 5}), 5U);  // every cell is a border cell
  EXPECT_EQ(ring_size({0, 0, 5, 1}), 5U);
  EXPECT_EQ(ring_size({0, 0, 1, 1}), 1U);
  EXPECT_EQ(ring_size({0, 0, 0, 3}), 0U);
  EXPECT_EQ(ring_size({0, 0, -4, 3}), 0U);
}

TEST(Halo, RingListsBorderSourcesInRowMajorOrder) {
  const MapGeometry g(4, 3, 4, 1, 1);
  ShaoLayerParams p;
  p.d_eps = 1.0;
  RegionField f(g, 0, p);
  auto tau = f.mutable_layer(Layer::Target);
  for (int32_t y = 0; y < 3; ++y) {
    for (int32_t x = 0; x < 4; ++x) tau[local(f.rect(), {x, y})] = static_cast<float>(10 * y + x);
  }
  f.set_obstacle_switch({3, 1});
  const HaloRing ring = f.begin_step();
  EXPECT_EQ(ring.region, 0U);
  EXPECT_EQ(ring.target, (std::vector<float>{0, 1, 2, 3, 10, 13, 20, 21, 22, 23}));
  // Sources, not values: the switched cell (3,1) carries v + k·d = 0 + 1.
  EXPECT_EQ(ring.obstacle, (std::vector<float>{0, 0, 0, 0, 0, 1, 0, 0, 0, 0}));
}

void fill_random(RegionField& f, uint64_t seed) {
  Rng rng(seed);
  for (float& v : f.mutable_layer(Layer::Target)) v = static_cast<float>(rng.uniform01());
  for (float& v : f.mutable_layer(Layer::Obstacle)) v = static_cast<float>(rng.uniform01());
}

void expect_same_layers(const RegionField& a, const RegionField& b) {
  for (const Layer l : {Layer::Target, Layer::Obstacle, Layer::Path}) {
    const auto va = a.layer(l);
    const auto vb = b.layer(l);
    ASSERT_EQ(va.size(), vb.size());
    for (std::size_t i = 0; i < va.size(); ++i) ASSERT_EQ(va[i], vb[i]) << layer_name(l) << " cell " << i;
  }
}

// A step diffuses the sources begin_step() took: a switch set before
// finish_step() joins the next step, a value written then is overwritten.
TEST(Layers, ASwitchOrAValueSetBetweenBeginAndFinishWaitsForTheNextStep) {
  const MapGeometry g(40, 12, 4, 1, 1);
  RegionField during(g, 0, ShaoLayerParams{});
  RegionField after(g, 0, ShaoLayerParams{});
  fill_random(during, 9);
  fill_random(after, 9);
  (void)during.begin_step();
  during.set_target_switch({3, 3}, true);
  during.set_obstacle_switch({30, 8});
  during.mutable_layer(Layer::Obstacle)[5] = 7.0F;
  during.finish_step();
  EXPECT_TRUE(during.target_switch({3, 3}));
  step(after);
  after.set_target_switch({3, 3}, true);
  after.set_obstacle_switch({30, 8});
  expect_same_layers(during, after);
  step(during);
  step(after);
  expect_same_layers(during, after);
}

TEST(Halo, WrongSizeOrForeignRingIsIgnoredWithoutCrashing) {
  const MapGeometry g(20, 10, 5, 2, 1);
  RegionField victim(g, 0, ShaoLayerParams{});
  RegionField control(g, 0, ShaoLayerParams{});
  RegionField neighbour(g, 1, ShaoLayerParams{});
  fill_random(victim, 1);
  fill_random(control, 1);
  fill_random(neighbour, 2);
  const HaloRing good = neighbour.begin_step();
  const Rect rect1 = g.region_rect(1);
  ASSERT_EQ(good.target.size(), ring_size(rect1));

  HaloRing short_target = good;
  short_target.target.pop_back();
  HaloRing long_obstacle = good;
  long_obstacle.obstacle.push_back(1.0F);
  HaloRing huge = good;
  for (float& v : huge.target) v = 1e30F;
  for (float& v : huge.obstacle) v = 1e30F;

  (void)victim.begin_step();
  (void)control.begin_step();
  victim.accept_halo(rect1, short_target);
  victim.accept_halo(rect1, long_obstacle);
  victim.accept_halo(rect1, HaloRing{});
  victim.accept_halo(Rect{}, HaloRing{});
  victim.accept_halo(Rect{INT32_MAX - 1, INT32_MAX - 1, INT32_MAX, INT32_MAX}, good);  // size mismatch
  victim.accept_halo(Rect{10, 0, -5, 10}, good);                                     // negative width
  // Right size but not adjacent: no cell in our halo.
  victim.accept_halo(Rect{INT32_MAX - 12, 3, 10, 10}, huge);
  victim.accept_halo(Rect{-20, -20, 10, 10}, huge);
  // Our own rect: its border cells are ours, not halo.
  victim.accept_halo(victim.rect(), huge);
  victim.finish_step();
  control.finish_step();
  expect_same_layers(victim, control);
}

TEST(Halo, MissingRingKeepsLastHaloValues) {
  // Region 1 is reset to the same values before each step, so its ring is
  // the same each time. `always` accepts it every step, `once` only in step
  // 1, `never` not at all: `once` must match `always`, and `never` must not
  // (else the test would not see the halo at all).
  const MapGeometry g(20, 10, 5, 2, 1);
  ShaoLayerParams p;
  p.g_tau = 0.5;
  p.g_eps = 0.5;
  RegionField always(g, 0, p);
  RegionField once(g, 0, p);
  RegionField never(g, 0, p);
  RegionField neighbour(g, 1, p);
  fill_random(always, 3);
  fill_random(once, 3);
  fill_random(never, 3);
  fill_random(neighbour, 4);
  const std::vector<float> n_tau = whole(neighbour, Layer::Target);
  const std::vector<float> n_eps = whole(neighbour, Layer::Obstacle);
  const Rect rect1 = g.region_rect(1);
  for (int s = 0; s < 3; ++s) {
    std::copy(n_tau.begin(), n_tau.end(), neighbour.mutable_layer(Layer::Target).begin());
    std::copy(n_eps.begin(), n_eps.end(), neighbour.mutable_layer(Layer::Obstacle).begin());
    const HaloRing ring = neighbour.begin_step();
    (void)always.begin_step();
    (void)once.begin_step();
    (void)never.begin_step();
    always.accept_halo(rect1, ring);
    if (s == 0) once.accept_halo(rect1, ring);
    always.finish_step();
    once.finish_step();
    never.finish_step();
    neighbour.finish_step();
  }
  expect_same_layers(always, once);
  EXPECT_NE(always.value(Layer::Target, {9, 5}), never.value(Layer::Target, {9, 5}));
}

// ---------------------------------------------------------------------------
// Split map == undivided map
// ---------------------------------------------------------------------------

struct SplitRun {
  int steps = 20;
  bool exchange_rings = true;
  // Each neighbour gets only the ring cells it reads (trim_halo), as the
  // place agents send them, and fills the rest with 0 (expand_halo).
  bool trimmed = false;
  // A field that is mostly +0 (the steps then skip what is +0 around): few
  // non-zero cells, some of them -0 or denormal, switches that change every
  // tenth step only, and now and then a value written into the field
  // between steps (mutable_layer).
  bool sparse = false;
};

// Runs the regions of `g` and the whole-map reference side by side from the
// same random start, with switches toggling and UAVs visiting, and returns the
// number of cells (over target, obstacle and path) whose float bits differ
// after the last step (stops at the first step with a difference).
int64_t split_mismatches(const MapGeometry& g, const SplitRun& run) {
  ShaoLayerParams p;
  p.e_tau = 0.1;
  p.g_tau = 0.3;
  p.d_tau = 1.0;
  p.e_eps = 0.05;
  p.g_eps = 0.25;
  p.d_eps = 0.7;
  const auto cells = static_cast<std::size_t>(g.map_rect().area());
  Rng rng(stream_seed(2020, "test", static_cast<uint32_t>(g.region_count())));

  // Whole-map state.
  std::vector<float> tau(cells), eps(cells), sigma(cells, static_cast<float>(p.sigma0));
  std::vector<uint8_t> k_tau(cells), k_eps(cells);
  // What a sparse field holds where it is not +0.
  const auto odd_value = [&](double scale) {
    switch (rng.uniform_below(4)) {
      case 0:
        return -0.0F;
      case 1:
        return std::numeric_limits<float>::denorm_min() * static_cast<float>(1 + rng.uniform_below(8));
      case 2:
        return std::numeric_limits<float>::min() * static_cast<float>(rng.uniform01());  // denormal
      default:
        return static_cast<float>(scale * rng.uniform01());
    }
  };
  for (std::size_t i = 0; i < cells; ++i) {
    if (run.sparse) {
      tau[i] = rng.uniform_below(40) == 0 ? odd_value(5.0) : 0.0F;
      eps[i] = rng.uniform_below(40) == 0 ? odd_value(3.0) : 0.0F;
      k_tau[i] = rng.uniform_below(200) == 0 ? 1 : 0;
      k_eps[i] = rng.uniform_below(400) == 0 ? 1 : 0;
      continue;
    }
    tau[i] = static_cast<float>(5.0 * rng.uniform01());
    eps[i] = static_cast<float>(3.0 * rng.uniform01());
    k_tau[i] = rng.uniform_below(10) == 0 ? 1 : 0;
    k_eps[i] = rng.uniform_below(20) == 0 ? 1 : 0;
  }

  std::vector<RegionField> fields;
  for (RegionId r = 0; r < g.region_count(); ++r) {
    RegionField& f = fields.emplace_back(g, r, p);
    const Rect rr = f.rect();
    for (int32_t y = rr.y0; y < rr.y0 + rr.h; ++y) {
      for (int32_t x = rr.x0; x < rr.x0 + rr.w; ++x) {
        const std::size_t gi = g.index({x, y});
        f.mutable_layer(Layer::Target)[local(rr, {x, y})] = tau[gi];
        f.mutable_layer(Layer::Obstacle)[local(rr, {x, y})] = eps[gi];
        f.set_target_switch({x, y}, k_tau[gi] != 0);
        if (k_eps[gi] != 0) f.set_obstacle_switch({x, y});
      }
    }
  }

  std::vector<float> next(cells);
  std::vector<float> delta(cells);
  const auto random_cell = [&] {
    return Cell{static_cast<int32_t>(rng.uniform_below(static_cast<uint32_t>(g.width()))),
                static_cast<int32_t>(rng.uniform_below(static_cast<uint32_t>(g.height())))};
  };
  for (int s = 0; s < run.steps; ++s) {
    if (run.sparse && s % 7 == 3) {
      // A value written between steps into the field that owns the cell.
      const Cell c = random_cell();
      const float v = odd_value(2.0);
      RegionField& f = fields[g.region_of(c)];
      const Layer l = s % 2 == 0 ? Layer::Target : Layer::Obstacle;
      f.mutable_layer(l)[local(f.rect(), c)] = v;
      (l == Layer::Target ? tau : eps)[g.index(c)] = v;
    }
    // Revisit switches come and go; obstacles get marked. Every field is
    // told; those that do not own the cell ignore it.
    for (int t = 0; t < (run.sparse && s % 10 != 0 ? 0 : 3); ++t) {
      const Cell c = random_cell();
      const bool on = k_tau[g.index(c)] == 0;
      k_tau[g.index(c)] = on ? 1 : 0;
      for (RegionField& f : fields) f.set_target_switch(c, on);
    }
    if (!run.sparse || s % 10 == 0) {
      const Cell obstacle = random_cell();
      k_eps[g.index(obstacle)] = 1;
      for (RegionField& f : fields) f.set_obstacle_switch(obstacle);
    }
    // UAV visits, Shao 2020 eq. (6), Shao 2020 eq. (7); the oracle accumulates in the same UAV order.
    std::fill(delta.begin(), delta.end(), 0.0F);
    for (int u = 0; u < 5; ++u) {
      const Cell uav = random_cell();
      for (RegionField& f : fields) f.add_path_visit(uav);
      for (int32_t y = 0; y < g.height(); ++y) {
        for (int32_t x = 0; x < g.width(); ++x) {
          const double dx = x - uav.x;
          const double dy = y - uav.y;
          const double dd = path_decrease(std::sqrt(dx * dx + dy * dy), p);
          if (dd != 0.0) delta[g.index({x, y})] += static_cast<float>(dd);
        }
      }
    }

    // Regions: publish, exchange every ring with every other region, finish.
    std::vector<HaloRing> rings;
    for (RegionField& f : fields) rings.push_back(f.begin_step());
    if (run.exchange_rings && !run.trimmed) {
      for (RegionField& f : fields) {
        for (RegionId r = 0; r < g.region_count(); ++r) {
          if (r != f.region()) f.accept_halo(g.region_rect(r), rings[r]);
        }
      }
    }
    if (run.exchange_rings && run.trimmed) {
      for (RegionField& f : fields) {
        for (RegionId r : g.neighbour_regions(f.region())) {
          const HaloMsg part = trim_halo({r, 0, rings[r].target, rings[r].obstacle}, g, f.region());
          const auto whole = expand_halo(part, g, f.region());
          if (!whole) return -1;
          f.accept_halo(g.region_rect(r), HaloRing{r, whole->target, whole->obstacle});
        }
      }
    }
    for (RegionField& f : fields) f.finish_step();

    // Whole map.
    reference_diffuse(g, tau, k_tau, p.e_tau, p.g_tau, p.d_tau, false, next);
    tau.swap(next);
    reference_diffuse(g, eps, k_eps, p.e_eps, p.g_eps, p.d_eps, true, next);
    eps.swap(next);
    for (std::size_t i = 0; i < cells; ++i) {
      sigma[i] = std::min(std::max(sigma[i] - delta[i], static_cast<float>(p.sigma_min)), static_cast<float>(p.sigma0));
    }

    int64_t mismatches = 0;
    for (const RegionField& f : fields) {
      const Rect rr = f.rect();
      for (int32_t y = rr.y0; y < rr.y0 + rr.h; ++y) {
        for (int32_t x = rr.x0; x < rr.x0 + rr.w; ++x) {
          const std::size_t gi = g.index({x, y});
          const std::size_t li = local(rr, {x, y});
          mismatches += std::bit_cast<uint32_t>(f.layer(Layer::Target)[li]) != std::bit_cast<uint32_t>(tau[gi]) ? 1 : 0;
          mismatches += std::bit_cast<uint32_t>(f.layer(Layer::Obstacle)[li]) != std::bit_cast<uint32_t>(eps[gi]) ? 1 : 0;
          mismatches += std::bit_cast<uint32_t>(f.layer(Layer::Path)[li]) != std::bit_cast<uint32_t>(sigma[gi]) ? 1 : 0;
        }
      }
    }
    if (mismatches != 0) return mismatches;
  }
  return 0;
}

// Both sides evaluate the same float expression per cell in the same order
// (see layers.cpp), so the results are bitwise equal, not just close.
TEST(Diffusion, AcrossRegionBorderMatchesUndividedMap) {
  // 37 x 29, tile 5 -> 8 x 6 tiles; 3 x 2 regions of 10/15/12 x 15/14 cells.
  EXPECT_EQ(split_mismatches(MapGeometry(37, 29, 5, 3, 2), SplitRun{}), 0);
  // Uneven splits, thin regions (one tile of 3 cells, last tile 1 cell wide).
  EXPECT_EQ(split_mismatches(MapGeometry(31, 7, 3, 4, 3), SplitRun{}), 0);
  EXPECT_EQ(split_mismatches(MapGeometry(10, 9, 1, 10, 9), SplitRun{.steps = 5}), 0);  // 1-cell regions
}

TEST(Diffusion, AcrossRegionBorderMatchesUndividedMapWhenEachNeighbourGetsOnlyTheCellsItReads) {
  EXPECT_EQ(split_mismatches(MapGeometry(37, 29, 5, 3, 2), SplitRun{.trimmed = true}), 0);
  EXPECT_EQ(split_mismatches(MapGeometry(31, 7, 3, 4, 3), SplitRun{.trimmed = true}), 0);
  EXPECT_EQ(split_mismatches(MapGeometry(10, 9, 1, 10, 9), SplitRun{.steps = 5, .trimmed = true}), 0);
}

TEST(Diffusion, ANeighbourReadsOneSideOfARingAndACornerNeighbourOneCell) {
  // 8 x 8 cells, 2 x 2 regions of 4 x 4. Region 0's ring, row-major over its
  // border: (0..3,0) 0..3, (0,1) 4, (3,1) 5, (0,2) 6, (3,2) 7, (0..3,3) 8..11.
  const MapGeometry g(8, 8, 4, 2, 2);
  const Rect r0 = g.region_rect(0);
  ASSERT_EQ(ring_size(r0), 12U);
  EXPECT_EQ(ring_indices_facing(g, r0, g.region_rect(1)), (std::vector<std::size_t>{3, 5, 7, 11}));  // east: x = 3
  EXPECT_EQ(ring_indices_facing(g, r0, g.region_rect(2)), (std::vector<std::size_t>{8, 9, 10, 11}));  // south: y = 3
  EXPECT_EQ(ring_indices_facing(g, r0, g.region_rect(3)), (std::vector<std::size_t>{11}));  // the corner (3,3)
  EXPECT_TRUE(ring_indices_facing(g, r0, r0).empty());
  // Trimmed for region 1 and expanded again: its 4 cells, 0 elsewhere.
  std::vector<float> ring(12);
  for (std::size_t i = 0; i < ring.size(); ++i) ring[i] = static_cast<float>(i + 1);
  const HaloMsg part = trim_halo({0, 7, ring, ring}, g, 1);
  EXPECT_EQ(part.target, (std::vector<float>{4, 6, 8, 12}));
  const auto whole = expand_halo(part, g, 1);
  ASSERT_TRUE(whole);
  EXPECT_EQ(whole->target, (std::vector<float>{0, 0, 0, 4, 0, 6, 0, 8, 0, 0, 0, 12}));
  EXPECT_EQ(whole->tick, 7U);
  // A part of the wrong size (the whole ring, or a forged one) is refused;
  // empty rings (no diffusion) pass as empty.
  EXPECT_FALSE(expand_halo({0, 7, ring, ring}, g, 1));
  EXPECT_FALSE(expand_halo({9, 7, {}, {}}, g, 1));
  EXPECT_TRUE(expand_halo({0, 7, {}, {}}, g, 1)->target.empty());
}

// A step computes only the chunks whose neighbourhood holds a source that is
// not +0 (layers.hpp): the cells it skips keep exactly what computing them
// gives, on both sides of region borders, with -0, denormals (which decay to
// the smallest denormal and stay there), switches turned on and off and
// values written between steps. Long enough for the fields to spread, thin
// out and underflow.
TEST(Diffusion, SkippingAllZeroNeighbourhoodsGivesTheBitsOfComputingEveryCell) {
  EXPECT_EQ(split_mismatches(MapGeometry(37, 29, 5, 3, 2), SplitRun{.steps = 300, .sparse = true}), 0);
  EXPECT_EQ(split_mismatches(MapGeometry(70, 45, 10, 2, 2), SplitRun{.steps = 200, .trimmed = true, .sparse = true}),
            0);
  EXPECT_EQ(split_mismatches(MapGeometry(31, 7, 3, 4, 3), SplitRun{.steps = 100, .sparse = true}), 0);
  EXPECT_EQ(split_mismatches(MapGeometry(53, 40, 4, 1, 1), SplitRun{.steps = 300, .sparse = true}), 0);
}

// The skipping needs combine(+0, +0) == +0; with coefficients that give -0
// there (1 - E < 0 is no paper's, but a scenario file could ask for it) every
// cell is computed, and a field of +0 turns into -0 as the equations say.
TEST(Diffusion, CoefficientsThatTurnZeroIntoMinusZeroComputeEveryCell) {
  const MapGeometry g(40, 3, 20, 1, 1);
  ShaoLayerParams p;
  p.e_tau = 2.0;  // (1 - E)(1 - G) < 0: (1-E)(1-G)·(+0) + G·(+0) is -0 + +0 = +0, G·nb too; still +0
  p.g_tau = 0.0;
  p.e_eps = 2.0;  // Shao 2020 eq. (3): (1 - E) < 0 multiplies a +0 brace: -0
  p.g_eps = 0.0;
  RegionField f(g, 0, p);
  step(f);
  for (const float v : f.layer(Layer::Target)) EXPECT_FALSE(std::signbit(v));
  for (const float v : f.layer(Layer::Obstacle)) EXPECT_TRUE(std::signbit(v) && v == 0.0F);
}

TEST(Diffusion, SingleRegionMatchesUndividedMap) {
  EXPECT_EQ(split_mismatches(MapGeometry(37, 29, 5, 1, 1), SplitRun{}), 0);
  EXPECT_EQ(split_mismatches(MapGeometry(1, 1, 1, 1, 1), SplitRun{.steps = 3}), 0);
  EXPECT_EQ(split_mismatches(MapGeometry(1, 6, 2, 1, 1), SplitRun{.steps = 3}), 0);
}

TEST(Diffusion, WithoutHaloExchangeRegionBordersDiffer) {
  // Guards the invariant test itself: dropping the rings must be visible.
  EXPECT_GT(split_mismatches(MapGeometry(37, 29, 5, 3, 2), SplitRun{.steps = 1, .exchange_rings = false}), 0);
}

}  // namespace
}  // namespace pheromesh::core
