#include "pheromesh/core/geodetic.hpp"

#include <cmath>
#include <numbers>

namespace pheromesh::core {

namespace {

// WGS84 (NIMA TR8350.2): semi-major axis [m] and flattening.
constexpr double kA = 6378137.0;
constexpr double kF = 1.0 / 298.257223563;
constexpr double kE2 = kF * (2.0 - kF);  // first eccentricity squared
constexpr double kDegToRad = std::numbers::pi / 180.0;

double sin2(double lat_deg) {
  const double s = std::sin(lat_deg * kDegToRad);
  return s * s;
}

// Into [-180, 180).
double wrap_lon(double lon_deg) {
  double l = std::fmod(lon_deg + 180.0, 360.0);
  if (l < 0) l += 360.0;
  return l - 180.0;
}

}  // namespace

double meridian_radius_m(double lat_deg) {
  const double w = 1.0 - kE2 * sin2(lat_deg);
  return kA * (1.0 - kE2) / (w * std::sqrt(w));
}

double prime_vertical_radius_m(double lat_deg) { return kA / std::sqrt(1.0 - kE2 * sin2(lat_deg)); }

GeoPoint map_to_geo(const GeoFrame& f, MapPoint p) {
  const double east_m = p.x * f.cell_size_m;
  const double north_m = -p.y * f.cell_size_m;
  const double lat0 = f.origin_lat_deg;
  const double dlat_rad = north_m / meridian_radius_m(lat0);
  const double dlon_rad = east_m / (prime_vertical_radius_m(lat0) * std::cos(lat0 * kDegToRad));
  return {lat0 + dlat_rad / kDegToRad, wrap_lon(f.origin_lon_deg + dlon_rad / kDegToRad),
          f.origin_alt_m + f.flight_height_m};
}

MapPoint geo_to_map(const GeoFrame& f, double lat_deg, double lon_deg) {
  const double lat0 = f.origin_lat_deg;
  const double north_m = (lat_deg - lat0) * kDegToRad * meridian_radius_m(lat0);
  const double dlon_deg = wrap_lon(lon_deg - f.origin_lon_deg);
  const double east_m = dlon_deg * kDegToRad * prime_vertical_radius_m(lat0) * std::cos(lat0 * kDegToRad);
  return {east_m / f.cell_size_m, -north_m / f.cell_size_m};
}

double heading_deg(double vx, double vy) {
  if (vx == 0.0 && vy == 0.0) return 0.0;
  // North is -y; atan2(east, north) is clockwise from north.
  double h = std::atan2(vx, -vy) / kDegToRad;
  if (h < 0) h += 360.0;
  return h >= 360.0 ? 0.0 : h;
}

}  // namespace pheromesh::core
