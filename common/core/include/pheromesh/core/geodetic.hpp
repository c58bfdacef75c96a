// Where the map lies on the Earth: the scenario's `geo` block
// (docs/scenario-format.md) and the conversion of a map position [cell] to
// WGS84 latitude, longitude and altitude and back, for a MAVLink ground
// station (docs/mavlink.md).
//
// The map is laid out as the web console draws it: column x grows to the
// east, row y grows to the south (row 0 is the northern edge), and the point
// (x, y) = (0, 0) is the centre of cell (0, 0), which lies at the origin.
//
// The conversion is a local tangent plane (equirectangular) one: a metre
// north is 1 / M(φ0) radians of latitude and a metre east 1 / (N(φ0) cos φ0)
// radians of longitude, M and N the WGS84 meridian and prime-vertical radii
// of curvature at the origin's latitude φ0. It is exact at the origin; away
// from it the longitude scale of the origin's parallel is used on every
// parallel, an error of about e · n · tan|φ0| / N [m] at e metres east and n
// metres north (0.16 m at 1 km x 1 km at 45°, 2.6 m at 4 km x 4 km at 45°),
// plus the curvature of the Earth, which is below 1 mm within 4 km. The
// latitude is limited to ±80° to keep tan φ0 small.
#pragma once

namespace pheromesh::core {

struct GeoFrame {
  double origin_lat_deg = 0.0;    // [deg] WGS84 latitude of the centre of cell (0, 0), [-80, 80]
  double origin_lon_deg = 0.0;    // [deg] WGS84 longitude of the centre of cell (0, 0), [-180, 180]
  double origin_alt_m = 0.0;      // [m] ground altitude above mean sea level, [-500, 9000]
  double cell_size_m = 1.0;       // [m] side of one cell, (0, 10000]
  double flight_height_m = 30.0;  // [m] height of the UAVs above the ground, [0, 10000]
};

// The scenario's valid ranges (checked by the scenario parser).
inline constexpr double kGeoMaxAbsLatDeg = 80.0;
inline constexpr double kGeoMinAltM = -500.0;
inline constexpr double kGeoMaxAltM = 9000.0;
inline constexpr double kGeoMaxCellSizeM = 10000.0;
inline constexpr double kGeoMaxFlightHeightM = 10000.0;

struct GeoPoint {
  double lat_deg = 0.0;  // [deg] WGS84
  double lon_deg = 0.0;  // [deg] WGS84, in [-180, 180)
  double alt_m = 0.0;    // [m] above mean sea level
};

struct MapPoint {
  double x = 0.0;  // [cell] east
  double y = 0.0;  // [cell] south
};

// The WGS84 point of map position (x, y) [cell] at the UAVs' flight
// altitude (origin_alt_m + flight_height_m).
GeoPoint map_to_geo(const GeoFrame& f, MapPoint p);
// The map position of a WGS84 point (its altitude is ignored); the inverse of
// map_to_geo up to rounding. A longitude across the antimeridian from the
// origin is taken the short way round.
MapPoint geo_to_map(const GeoFrame& f, double lat_deg, double lon_deg);

// WGS84 radii of curvature at latitude lat_deg [m]: meridian (M) and prime
// vertical (N).
double meridian_radius_m(double lat_deg);
double prime_vertical_radius_m(double lat_deg);

// A heading [deg] clockwise from north in [0, 360) of a velocity (vx east,
// vy south) [cell/tick]; 0 for a UAV at rest.
double heading_deg(double vx, double vy);

}  // namespace pheromesh::core
