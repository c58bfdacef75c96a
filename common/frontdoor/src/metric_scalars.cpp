#include "pheromesh/frontdoor/metric_scalars.hpp"

#include <limits>

namespace pheromesh::frontdoor {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void flatten(const nlohmann::json& j, const std::string& prefix, Scalars& out) {
  for (const auto& [key, v] : j.items()) {
    const std::string name = prefix.empty() ? key : prefix + "." + key;
    if (v.is_object()) {
      flatten(v, name, out);
    } else if (v.is_boolean()) {
      out[name] = v.get<bool>() ? 1.0 : 0.0;
    } else if (v.is_number()) {
      out[name] = v.get<double>();
    } else if (v.is_null()) {
      out[name] = kNaN;
    }
    // strings and arrays: not scalar metrics
  }
}

}  // namespace

Scalars flatten_scalars(const nlohmann::json& metrics) {
  Scalars out;
  if (metrics.is_object()) flatten(metrics, "", out);
  out.erase("seed");
  return out;
}

bool is_timing_metric(const std::string& name) { return name == "wall_seconds" || name == "uav_steps_per_second"; }

}  // namespace pheromesh::frontdoor
