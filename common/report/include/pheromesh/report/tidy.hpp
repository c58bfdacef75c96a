// The tidy outputs of a run (docs/outputs.md): one observation per row, one
// variable per column, a header line, numbers that read back exactly.
//   series.csv        one row per tick (core::TickRow)
//   tracks.csv        one row per UAV and tick (core::TrackRow), on request
//   final_field.csv   one row per layer and cell of the final field
// Written atomically (core/atomic_file.hpp) by the ground station and the
// simulator alike, so a lockstep run's files equal the simulator's byte for
// byte.
#pragma once

#include <string>
#include <vector>

#include "pheromesh/core/result.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/report/report.hpp"

namespace pheromesh::report {

// The shortest text that reads back as exactly `v` (std::to_chars); "NaN",
// "Inf" and "-Inf" as R and pandas read them.
std::string number_text(double v);
std::string number_text(float v);

// The header of series.csv and tracks.csv (also what docs/outputs.md lists).
inline constexpr const char* kSeriesHeader =
    "tick,coverage,covered_cells,targets_found,uavs_reporting,deposits_sent,deposits_applied,deposits_rejected";
inline constexpr const char* kTracksHeader = "tick,uav,x,y,role";
inline constexpr const char* kFieldHeader = "layer,x,y,value";

std::string series_csv(const std::vector<core::TickRow>& rows);
std::string tracks_csv(const std::vector<core::TrackRow>& rows);

// Each returns the bytes written, or the error of a file it could not write.
core::Result<std::size_t> write_series_csv(const std::string& path, const std::vector<core::TickRow>& rows);
core::Result<std::size_t> write_tracks_csv(const std::string& path, const std::vector<core::TrackRow>& rows);
// Layer by layer, row by row (y), cell by cell (x) - the order of
// final_field.txt; `value` may return NaN for a cell it does not know.
core::Result<std::size_t> write_field_csv(const std::string& path, const core::MapGeometry& geo,
                             const std::vector<std::string>& layers, const FieldReader& value);

}  // namespace pheromesh::report
