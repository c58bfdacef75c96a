// The scenario's geodetic frame (common/core/src/field/geodetic.cpp) and its
// `geo` block (common/core/src/scenario/scenario.cpp).
#include "pheromesh/core/geodetic.hpp"

#include <gtest/gtest.h>

#include <string>

#include "pheromesh/core/scenario.hpp"

namespace pheromesh::core {
namespace {

constexpr double kDegTol = 1e-10;  // [deg] ~ 0.01 mm

// Worked by hand: WGS84 a = 6378137 m, e² = f(2 - f) with f = 1/298.257223563
// = 0.00669437999014. At the equator N = a and M = a(1 - e²) = 6335439.327 m.
// 1000 m east: 1000 / 6378137 rad = 0.00898315284 deg (the textbook 1° of
// longitude at the equator = 111319.49 m); 1000 m north: 1000 / 6335439.327
// rad = 0.00904369477 deg (1° of latitude there = 110574.27 m).
TEST(Geodetic, RadiiAtTheEquatorAreTheSemiMajorAxisAndItsMeridianShortening) {
  EXPECT_NEAR(prime_vertical_radius_m(0.0), 6378137.0, 1e-6);
  EXPECT_NEAR(meridian_radius_m(0.0), 6335439.327, 1e-3);
}

TEST(Geodetic, AKilometreEastAndNorthOfNullIslandIsTheTextbookDegree) {
  GeoFrame f;  // the default: 0° N 0° E, 1 m cells, 30 m above sea level ground 0 m
  const GeoPoint east = map_to_geo(f, {1000.0, 0.0});
  EXPECT_NEAR(east.lat_deg, 0.0, kDegTol);
  EXPECT_NEAR(east.lon_deg, 0.00898315284, kDegTol);
  EXPECT_DOUBLE_EQ(east.alt_m, 30.0);
  // Row y grows to the south: y = -1000 is 1 km north.
  const GeoPoint north = map_to_geo(f, {0.0, -1000.0});
  EXPECT_NEAR(north.lat_deg, 0.00904369477, kDegTol);
  EXPECT_NEAR(north.lon_deg, 0.0, kDegTol);
}

// At 45°: M = a(1 - e²) / (1 - e²/2)^1.5 = 6367381.816 m, N = a / sqrt(1 -
// e²/2) = 6388838.290 m. 100 cells of 2 m east = 200 m: 200 / (N cos 45°) rad
// = 0.00253656345 deg; 50 cells south = 100 m: -100 / M rad = -0.00089983263 deg.
TEST(Geodetic, CellSizeAndTheOriginsLatitudeScaleBothAxes) {
  GeoFrame f;
  f.origin_lat_deg = 45.0;
  f.origin_lon_deg = 7.0;
  f.origin_alt_m = 250.0;
  f.cell_size_m = 2.0;
  f.flight_height_m = 40.0;
  EXPECT_NEAR(meridian_radius_m(45.0), 6367381.816, 1e-3);
  EXPECT_NEAR(prime_vertical_radius_m(45.0), 6388838.290, 1e-3);
  const GeoPoint p = map_to_geo(f, {100.0, 50.0});
  EXPECT_NEAR(p.lon_deg, 7.0 + 0.00253656345, kDegTol);
  EXPECT_NEAR(p.lat_deg, 45.0 - 0.00089983263, kDegTol);
  EXPECT_DOUBLE_EQ(p.alt_m, 290.0);
}

TEST(Geodetic, GeoToMapUndoesMapToGeo) {
  GeoFrame f;
  f.origin_lat_deg = -33.9;
  f.origin_lon_deg = 151.2;
  f.cell_size_m = 5.0;
  for (const MapPoint m : {MapPoint{0, 0}, MapPoint{4095.0, 4095.0}, MapPoint{12.25, 3.5}, MapPoint{-7.0, 800.0}}) {
    const GeoPoint g = map_to_geo(f, m);
    const MapPoint back = geo_to_map(f, g.lat_deg, g.lon_deg);
    EXPECT_NEAR(back.x, m.x, 1e-6) << m.x << "," << m.y;
    EXPECT_NEAR(back.y, m.y, 1e-6) << m.x << "," << m.y;
  }
}

TEST(Geodetic, LongitudeWrapsAtTheAntimeridianBothWays) {
  GeoFrame f;
  f.origin_lon_deg = 179.999;
  const GeoPoint g = map_to_geo(f, {1000.0, 0.0});  // +0.00898° east: past 180°
  EXPECT_NEAR(g.lon_deg, -180.0 + 0.00798315284, kDegTol);
  const MapPoint back = geo_to_map(f, g.lat_deg, g.lon_deg);
  EXPECT_NEAR(back.x, 1000.0, 1e-6);
}

TEST(Geodetic, HeadingIsClockwiseFromNorthWithRowsGrowingSouth) {
  EXPECT_DOUBLE_EQ(heading_deg(0.0, -1.0), 0.0);  // up the map: north
  EXPECT_DOUBLE_EQ(heading_deg(1.0, 0.0), 90.0);  // east
  EXPECT_DOUBLE_EQ(heading_deg(0.0, 1.0), 180.0);
  EXPECT_DOUBLE_EQ(heading_deg(-1.0, 0.0), 270.0);
  EXPECT_DOUBLE_EQ(heading_deg(1.0, 1.0), 135.0);
  EXPECT_DOUBLE_EQ(heading_deg(0.0, 0.0), 0.0);
}

constexpr const char* kMap = "map { width: 20 height: 20 }\n";

TEST(ScenarioGeo, AbsentBlockGivesTheDocumentedDefault) {
  const auto r = parse_scenario(kMap, "geo.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_DOUBLE_EQ(r.value().geo.origin_lat_deg, 0.0);
  EXPECT_DOUBLE_EQ(r.value().geo.origin_lon_deg, 0.0);
  EXPECT_DOUBLE_EQ(r.value().geo.cell_size_m, 1.0);
  EXPECT_DOUBLE_EQ(r.value().geo.flight_height_m, 30.0);
}

TEST(ScenarioGeo, FieldsAreRead) {
  const auto r = parse_scenario(std::string(kMap) +
                                    "geo { origin_lat_deg: 48.1 origin_lon_deg: -1.5 origin_alt_m: 35 cell_size_m: 2.5 "
                                    "flight_height_m: 0 }\n",
                                "geo.textproto");
  ASSERT_TRUE(r.ok()) << r.error().message;
  const GeoFrame& g = r.value().geo;
  EXPECT_DOUBLE_EQ(g.origin_lat_deg, 48.1);
  EXPECT_DOUBLE_EQ(g.origin_lon_deg, -1.5);
  EXPECT_DOUBLE_EQ(g.origin_alt_m, 35.0);
  EXPECT_DOUBLE_EQ(g.cell_size_m, 2.5);
  EXPECT_DOUBLE_EQ(g.flight_height_m, 0.0);
}

TEST(ScenarioGeo, OutOfRangeFieldsNameFileLineAndField) {
  const auto r = parse_scenario(std::string(kMap) +
                                    "geo {\n"
                                    "  origin_lat_deg: 85\n"
                                    "  cell_size_m: 0\n"
                                    "  origin_lon_deg: nan\n"
                                    "}\n",
                                "geo.textproto");
  ASSERT_FALSE(r.ok());
  const std::string& m = r.error().message;
  EXPECT_NE(m.find("geo.textproto:3:3: field 'geo.origin_lat_deg': must be in [-80, 80] (got 85)"), std::string::npos)
      << m;
  EXPECT_NE(m.find("geo.textproto:4:3: field 'geo.cell_size_m': must be in (0, 10000]"), std::string::npos) << m;
  EXPECT_NE(m.find("geo.textproto:5:3: field 'geo.origin_lon_deg': must be a finite number"), std::string::npos) << m;
}

}  // namespace
}  // namespace pheromesh::core
