// What the bound types of bindings.cpp hold: pointers into the UAV's tick,
// set by the policy's wrapper (pypolicy.cpp) for the length of one step.
#pragma once

#include <cstdint>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/core/world.hpp"

namespace pheromesh::pypolicy::detail {

// pheromesh.View: the UavView of the step under way (null between steps).
struct ViewHandle {
  const core::UavView* view = nullptr;
};

// pheromesh.Actions: the UavActions of the step under way (null between steps).
struct ActionsHandle {
  core::UavActions* out = nullptr;
  const core::MapGeometry* geo = nullptr;
  const core::World* world = nullptr;
  int layers = 0;          // the policy's layers: a deposit names one of them
  bool state_set = false;  // set_state was called in this step
};

// pheromesh.Uav: one UAV, for the life of its policy.
struct UavHandle {
  uint32_t id = 0;
  core::Cell start{};
  uint64_t seed = 0;   // the run's seed
  uint32_t ticks = 0;  // the run's length [tick]
  const core::MapGeometry* geo = nullptr;
  const core::World* world = nullptr;
  core::Rng rng{0};  // the UAV's stream: core::stream_seed(seed, "python-uav", id)
};

// pheromesh.Region: the region a place model keeps.
struct RegionHandle {
  uint32_t id = 0;
  core::Rect rect{};
  int layers = 0;
};

// pheromesh.Field: the final field, during a call of field_summary.
struct FieldHandle {
  const core::FieldLookup* lookup = nullptr;
  int32_t width = 0, height = 0;
  int layers = 0;
};

}  // namespace pheromesh::pypolicy::detail
