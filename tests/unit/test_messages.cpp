// Semantic checks of received samples: each bad field gives a reason, never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/marks.hpp"
#include "pheromesh/core/messages.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// 23 x 20 cells, tiles of 5 (the last tile column is 3 wide), 2 x 2 regions.
MapGeometry test_geometry() { return {23, 20, 5, 2, 2}; }

using test::expect_reason;

DepositMsg good_mark(const MapGeometry& geo, RegionId owner) {
  const Rect r = geo.region_rect(owner);
  DepositMsg d;
  d.region = owner;
  d.kind = static_cast<uint8_t>(DepositKind::TargetMark);
  d.cell = Cell{r.x0 + 1, r.y0 + 1};
  d.amount = 1.0F;
  return d;
}

TileMsg good_tile(const MapGeometry& geo, TileCoord t) {
  const Rect r = geo.tile_rect(t);
  TileMsg m;
  m.layer = static_cast<uint8_t>(Layer::Path);
  m.tile = t;
  m.region = geo.region_of_tile(t);
  m.width = static_cast<uint16_t>(r.w);
  m.height = static_cast<uint16_t>(r.h);
  m.values.assign(static_cast<std::size_t>(r.area()), 0.5F);
  return m;
}

HaloMsg good_halo(const MapGeometry& geo, RegionId region) {
  HaloMsg h;
  h.region = region;
  const std::size_t n = ring_size(geo.region_rect(region));
  h.target.assign(n, 0.25F);
  h.obstacle.assign(n, 0.0F);
  return h;
}

TEST(CheckDeposit, AcceptsAWellFormedMarkInsideTheOwnersRegion) {
  const MapGeometry geo = test_geometry();
  for (RegionId owner = 0; owner < geo.region_count(); ++owner) {
    EXPECT_FALSE(check_deposit(good_mark(geo, owner), geo, owner, kLayerCount).has_value()) << owner;
  }
}

TEST(CheckDeposit, RejectsNonFiniteNegativeOrHugeAmounts) {
  const MapGeometry geo = test_geometry();
  DepositMsg d = good_mark(geo, 0);
  d.amount = kNaN;
  expect_reason(check_deposit(d, geo, 0, kLayerCount), "not finite");
  d.amount = kInf;
  expect_reason(check_deposit(d, geo, 0, kLayerCount), "not finite");
  d.amount = -kInf;
  expect_reason(check_deposit(d, geo, 0, kLayerCount), "not finite");
  d.amount = -0.5F;
  expect_reason(check_deposit(d, geo, 0, kLayerCount), "amount");
  d.amount = 2e6F;
  expect_reason(check_deposit(d, geo, 0, kLayerCount), "amount");
  d.amount = 0.0F;
  EXPECT_FALSE(check_deposit(d, geo, 0, kLayerCount).has_value());
}

TEST(CheckDeposit, RejectsAnUnknownKind) {
  const MapGeometry geo = test_geometry();
  DepositMsg d = good_mark(geo, 0);
  d.kind = kDepositKindCount;
  expect_reason(check_deposit(d, geo, 0, kLayerCount), "kind");
  d.kind = 255;
  expect_reason(check_deposit(d, geo, 0, kLayerCount), "kind");
}

TEST(CheckDeposit, RejectsACellOutsideTheMap) {
  const MapGeometry geo = test_geometry();
  DepositMsg d = good_mark(geo, 0);
  d.kind = static_cast<uint8_t>(DepositKind::PathVisit);
  for (const Cell c : {Cell{-1, 0}, Cell{23, 0}, Cell{0, 20}, Cell{std::numeric_limits<int32_t>::min(), 0}}) {
    d.cell = c;
    expect_reason(check_deposit(d, geo, 0, kLayerCount), "outside the map");
  }
}

TEST(CheckDeposit, RejectsADepositAddressedToAnotherRegion) {
  const MapGeometry geo = test_geometry();
  DepositMsg d = good_mark(geo, 0);
  d.region = 1;
  expect_reason(check_deposit(d, geo, 0, kLayerCount), "region");
  d.region = 9999;
  expect_reason(check_deposit(d, geo, 0, kLayerCount), "region");
  // An owner that does not exist rejects everything, without touching the geometry.
  expect_reason(check_deposit(good_mark(geo, 0), geo, 9999, kLayerCount), "region");
}

TEST(CheckDeposit, RejectsMarksOutsideTheOwnersRegionButAcceptsNearbyPathVisits) {
  const MapGeometry geo = test_geometry();
  const Rect r0 = geo.region_rect(0);
  const Cell outside{r0.x0 + r0.w, r0.y0};  // first column of the neighbour region
  ASSERT_TRUE(geo.in_map(outside));
  DepositMsg d = good_mark(geo, 0);
  d.cell = outside;
  expect_reason(check_deposit(d, geo, 0, kLayerCount), "outside region");
  d.kind = static_cast<uint8_t>(DepositKind::ObstacleMark);
  expect_reason(check_deposit(d, geo, 0, kLayerCount), "outside region");
  d.kind = static_cast<uint8_t>(DepositKind::PathVisit);
  EXPECT_FALSE(check_deposit(d, geo, 0, kLayerCount).has_value());
}

TEST(CheckTile, AcceptsWellFormedTilesIncludingTheNarrowLastColumn) {
  const MapGeometry geo = test_geometry();
  EXPECT_FALSE(check_tile(good_tile(geo, TileCoord{0, 0}), geo, kLayerCount).has_value());
  const TileMsg edge = good_tile(geo, TileCoord{4, 3});
  EXPECT_EQ(edge.width, 3);
  EXPECT_FALSE(check_tile(edge, geo, kLayerCount).has_value());
}

TEST(CheckTile, RejectsATileOutsideTheMap) {
  const MapGeometry geo = test_geometry();
  TileMsg t = good_tile(geo, TileCoord{0, 0});
  for (const TileCoord c : {TileCoord{5, 0}, TileCoord{0, 4}, TileCoord{-1, 0}, TileCoord{0, -7}}) {
    t.tile = c;
    expect_reason(check_tile(t, geo, kLayerCount), "outside the map");
  }
}

TEST(CheckTile, RejectsAnUnknownLayer) {
  const MapGeometry geo = test_geometry();
  TileMsg t = good_tile(geo, TileCoord{1, 1});
  t.layer = kLayerCount;
  expect_reason(check_tile(t, geo, kLayerCount), "layer");
}

TEST(CheckTile, RejectsOversizedValues) {
  const MapGeometry geo = test_geometry();
  TileMsg t = good_tile(geo, TileCoord{1, 1});
  t.values.assign(kMaxTileCells + 1, 0.0F);
  expect_reason(check_tile(t, geo, kLayerCount), "more than");
}

TEST(CheckTile, RejectsSizesThatDoNotMatchTheTile) {
  const MapGeometry geo = test_geometry();
  TileMsg t = good_tile(geo, TileCoord{4, 0});  // 3 x 5
  t.width = 5;
  t.values.assign(25, 0.0F);
  expect_reason(check_tile(t, geo, kLayerCount), "does not match");
  t = good_tile(geo, TileCoord{4, 0});
  t.values.pop_back();
  expect_reason(check_tile(t, geo, kLayerCount), "values for");
}

TEST(CheckTile, RejectsNonFiniteValues) {
  const MapGeometry geo = test_geometry();
  TileMsg t = good_tile(geo, TileCoord{2, 2});
  t.values[7] = kNaN;
  expect_reason(check_tile(t, geo, kLayerCount), "not finite");
  t.values[7] = -kInf;
  expect_reason(check_tile(t, geo, kLayerCount), "not finite");
}

TEST(CheckUavState, AcceptsPositionsWithinTheMapMargin) {
  const MapGeometry geo = test_geometry();
  UavStateMsg s;
  s.x = -0.5;
  s.y = 19.5;
  s.heading = 7;
  s.role = static_cast<uint8_t>(Role::Follower);
  EXPECT_FALSE(check_uav_state(s, geo).has_value());
  s.x = 23.0;
  s.y = -1.0;
  EXPECT_FALSE(check_uav_state(s, geo).has_value());
}

TEST(CheckUavState, RejectsNonFiniteValuesPositionsOffTheMapAndUnknownEnums) {
  const MapGeometry geo = test_geometry();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  UavStateMsg s;
  s.x = nan;
  expect_reason(check_uav_state(s, geo), "non-finite");
  s = UavStateMsg{};
  s.vy = std::numeric_limits<double>::infinity();
  expect_reason(check_uav_state(s, geo), "non-finite");
  s = UavStateMsg{};
  s.x = 23.01;
  expect_reason(check_uav_state(s, geo), "outside the map");
  s = UavStateMsg{};
  s.y = -1.5;
  expect_reason(check_uav_state(s, geo), "outside the map");
  s = UavStateMsg{};
  s.heading = 8;
  expect_reason(check_uav_state(s, geo), "heading");
  s = UavStateMsg{};
  s.role = 3;
  expect_reason(check_uav_state(s, geo), "role");
}

TEST(CheckHalo, AcceptsRingsOfTheRegionsBorderSize) {
  const MapGeometry geo = test_geometry();
  for (RegionId r = 0; r < geo.region_count(); ++r) {
    EXPECT_FALSE(check_halo(good_halo(geo, r), geo).has_value()) << r;
  }
}

TEST(CheckHalo, RejectsAnUnknownRegion) {
  const MapGeometry geo = test_geometry();
  HaloMsg h = good_halo(geo, 0);
  h.region = geo.region_count();
  expect_reason(check_halo(h, geo), "unknown region");
}

TEST(CheckHalo, RejectsRingsOfTheWrongSizeOrOversizedRings) {
  const MapGeometry geo = test_geometry();
  HaloMsg h = good_halo(geo, 1);
  h.obstacle.pop_back();
  expect_reason(check_halo(h, geo), "do not match");
  h = good_halo(geo, 1);
  h.target.push_back(0.0F);
  expect_reason(check_halo(h, geo), "do not match");
  h = good_halo(geo, 1);
  h.target.assign(kMaxRingCells + 1, 0.0F);
  expect_reason(check_halo(h, geo), "longer than");
}

TEST(CheckHalo, RejectsNonFiniteValues) {
  const MapGeometry geo = test_geometry();
  HaloMsg h = good_halo(geo, 3);
  h.obstacle.back() = kInf;
  expect_reason(check_halo(h, geo), "not finite");
}

TEST(Messages, TargetEventKindsAreTheMarkEventKindsWithNames) {
  EXPECT_EQ(static_cast<int>(TargetEventKind::FirstMarked), static_cast<int>(MarkEvent::Kind::FirstMarked));
  EXPECT_EQ(static_cast<int>(TargetEventKind::RevisitDue), static_cast<int>(MarkEvent::Kind::RevisitDue));
  EXPECT_EQ(static_cast<int>(TargetEventKind::Revisited), static_cast<int>(MarkEvent::Kind::Revisited));
  EXPECT_STREQ(to_string(TargetEventKind::RevisitDue), "due for a revisit");
  EXPECT_STREQ(to_string(static_cast<TargetEventKind>(9)), "unknown");
  EXPECT_EQ(process_key(kRoleGround, 0) >> 24U, 3U);
}

TEST(UplinkSamples, AStateCarriesItsTicksDepositsInSamplesOfAtMostTheBoundEachWithTheWholeState) {
  UavStateMsg s;
  s.uav = 3;
  s.tick = 17;
  s.x = 4.5;
  s.deposits_sent = 200;
  // None: one sample, the state alone.
  auto samples = uplink_samples(s, {});
  ASSERT_EQ(samples.size(), 1U);
  EXPECT_TRUE(samples[0].deposits.empty());
  EXPECT_EQ(samples[0].tick, 17U);
  // 64 + 64 + 2 = 130 deposits: three samples, in order, each the same state.
  std::vector<DepositMsg> deposits(2 * kMaxUplinkDeposits + 2);
  for (std::size_t i = 0; i < deposits.size(); ++i) deposits[i].seq = static_cast<uint32_t>(71 + i);
  samples = uplink_samples(s, deposits);
  ASSERT_EQ(samples.size(), 3U);
  EXPECT_EQ(samples[0].deposits.size(), kMaxUplinkDeposits);
  EXPECT_EQ(samples[1].deposits.size(), kMaxUplinkDeposits);
  ASSERT_EQ(samples[2].deposits.size(), 2U);
  EXPECT_EQ(samples[0].deposits.front().seq, 71U);
  EXPECT_EQ(samples[1].deposits.front().seq, 71U + 64U);
  EXPECT_EQ(samples[2].deposits.back().seq, 71U + 129U);
  for (const auto& m : samples) {
    EXPECT_EQ(m.uav, 3U);
    EXPECT_EQ(m.tick, 17U);
    EXPECT_EQ(m.x, 4.5);
    EXPECT_EQ(m.deposits_sent, 200U);
  }
  // Exactly the bound: one sample.
  deposits.resize(kMaxUplinkDeposits);
  EXPECT_EQ(uplink_samples(s, deposits).size(), 1U);
  // payload_bytes counts what a state carries.
  EXPECT_EQ(payload_bytes(samples[2]), sizeof(UavStateMsg) + 2 * sizeof(DepositMsg));
}

TEST(DepositBatches, AForwardersDepositsForOneOwnerGoInBatchesOfAtMostTheBoundInOrder) {
  // None: no sample at all (nothing to forward).
  EXPECT_TRUE(deposit_batches(2, 9, {}).empty());
  // 256 + 256 + 3 = 515 deposits: three batches, in order, each naming the
  // forwarder and its tick.
  std::vector<DepositMsg> deposits(2 * kMaxForwardDeposits + 3);
  for (std::size_t i = 0; i < deposits.size(); ++i) deposits[i].seq = static_cast<uint32_t>(11 + i);
  const auto batches = deposit_batches(2, 9, deposits);
  ASSERT_EQ(batches.size(), 3U);
  EXPECT_EQ(batches[0].deposits.size(), kMaxForwardDeposits);
  EXPECT_EQ(batches[1].deposits.size(), kMaxForwardDeposits);
  ASSERT_EQ(batches[2].deposits.size(), 3U);
  EXPECT_EQ(batches[0].deposits.front().seq, 11U);
  EXPECT_EQ(batches[1].deposits.front().seq, 11U + 256U);
  EXPECT_EQ(batches[2].deposits.back().seq, 11U + 514U);
  for (const auto& b : batches) {
    EXPECT_EQ(b.forwarder, 2U);
    EXPECT_EQ(b.tick, 9U);
  }
  // Exactly the bound: one batch.
  deposits.resize(kMaxForwardDeposits);
  EXPECT_EQ(deposit_batches(2, 9, deposits).size(), 1U);
  EXPECT_EQ(payload_bytes(batches[2]), sizeof(DepositBatchMsg) + 3 * sizeof(DepositMsg));
}

}  // namespace
}  // namespace pheromesh::core
