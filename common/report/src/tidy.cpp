#include "pheromesh/report/tidy.hpp"

#include <charconv>
#include <cmath>

#include "pheromesh/core/atomic_file.hpp"

namespace pheromesh::report {

namespace {

template <typename T>
std::string shortest(T v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "Inf" : "-Inf";
  char buf[64];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : std::string("NaN");
}

}  // namespace

std::string number_text(double v) { return shortest(v); }
std::string number_text(float v) { return shortest(v); }

std::string series_csv(const std::vector<core::TickRow>& rows) {
  std::string out = std::string(kSeriesHeader) + "\n";
  out.reserve(out.size() + rows.size() * 48);
  for (const core::TickRow& r : rows) {
    out += std::to_string(r.tick) + ',' + number_text(r.coverage) + ',' + std::to_string(r.covered_cells) + ',' +
           std::to_string(r.targets_found) + ',' + std::to_string(r.uavs_reporting) + ',' +
           std::to_string(r.deposits_sent) + ',' + std::to_string(r.deposits_applied) + ',' +
           std::to_string(r.deposits_rejected) + '\n';
  }
  return out;
}

std::string tracks_csv(const std::vector<core::TrackRow>& rows) {
  std::string out = std::string(kTracksHeader) + "\n";
  out.reserve(out.size() + rows.size() * 32);
  for (const core::TrackRow& r : rows) {
    out += std::to_string(r.tick) + ',' + std::to_string(r.uav) + ',' + number_text(r.x) + ',' + number_text(r.y) +
           ',' + core::role_name(r.role) + '\n';
  }
  return out;
}

core::Result<std::size_t> write_series_csv(const std::string& path, const std::vector<core::TickRow>& rows) {
  return core::write_file_atomically(path, series_csv(rows));
}

core::Result<std::size_t> write_tracks_csv(const std::string& path, const std::vector<core::TrackRow>& rows) {
  return core::write_file_atomically(path, tracks_csv(rows));
}

core::Result<std::size_t> write_field_csv(const std::string& path, const core::MapGeometry& geo,
                                          const std::vector<std::string>& layers, const FieldReader& value) {
  // Streamed: a 1024 x 1024 map with three layers is ~3 M rows.
  auto out = core::AtomicFile::create(path);
  if (!out) return out.error();
  std::string line = std::string(kFieldHeader) + "\n";
  out->write(line);
  for (int l = 0; l < static_cast<int>(layers.size()); ++l) {
    const std::string prefix = layers[static_cast<std::size_t>(l)] + ',';
    for (int32_t y = 0; y < geo.height(); ++y) {
      for (int32_t x = 0; x < geo.width(); ++x) {
        line = prefix + std::to_string(x) + ',' + std::to_string(y) + ',' + number_text(value(l, {x, y})) + '\n';
        out->write(line);
      }
    }
  }
  return out->commit();
}

}  // namespace pheromesh::report
