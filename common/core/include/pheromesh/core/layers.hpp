// Shao 2020 semantic pheromone layers (Shao 2020 eq. (1), Shao 2020 eq. (2), Shao 2020 eq. (3), Shao 2020 eq. (4), Shao 2020 eq. (5), Shao 2020 eq. (6), Shao 2020 eq. (7), Shao 2020 eq. (8)) over one region, with a
// one-cell halo so that diffusion across region borders equals diffusion on
// the undivided map. Diffusion radius is 1 cell (8-neighbourhood); the halo
// width is 1 cell; the constructor's geometry guarantees radius <= halo.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "pheromesh/core/grid.hpp"
#include "pheromesh/core/shao_params.hpp"

namespace pheromesh::core {

enum class Layer : uint8_t { Target = 0, Obstacle = 1, Path = 2, TargetState = 3 };
inline constexpr int kLayerCount = 4;
const char* layer_name(Layer l);

// Values of the TargetState layer.
inline constexpr float kTargetUnknown = 0.0F;  // no target marked here
inline constexpr float kTargetMarked = 1.0F;   // marked, revisit timer running
inline constexpr float kTargetDue = 2.0F;      // revisit due: kτ = 1, emitting target pheromone

// Path-pheromone decrease at distance `dist` [cell] from a UAV, Shao 2020 eq. (7).
double path_decrease(double dist, const ShaoLayerParams& p);

// The border ring of a region: the source values s = v + k·d of the target and
// obstacle layers (the quantity neighbours diffuse from, Shao 2020 eq. (2) and Shao 2020 eq. (4)) for
// every cell on the region's border, in row-major order over the rect's cells
// that satisfy x == x0 || x == x0+w-1 || y == y0 || y == y0+h-1.
struct HaloRing {
  RegionId region = 0;
  std::vector<float> target;
  std::vector<float> obstacle;
};
std::size_t ring_size(const Rect& r);
// Calls f(x, y) for the cells of a w x h rectangle's border ring (local
// coordinates), in the order a HaloRing carries them: rows from the top, the
// first and the last row whole, every other row its first and last cell.
template <typename F>
void for_each_ring_cell(std::size_t w, std::size_t h, F&& f) {
  for (std::size_t y = 0; y < h; ++y) {
    if (y == 0 || y + 1 == h) {
      for (std::size_t x = 0; x < w; ++x) f(x, y);
    } else {
      f(0, y);
      if (w > 1) f(w - 1, y);
    }
  }
}
// Index of cell (x, y) in the border ring of `r` (the order above), or
// nothing when the cell is not on r's border.
std::optional<std::size_t> ring_index(const Rect& r, int64_t x, int64_t y);
// Local traffic (issue 25): the indices of `sender`'s border ring that lie in
// `receiver`'s 1-cell halo on the map - the only ring cells the receiver's
// diffusion reads (RegionField::accept_halo) - in ascending order. A region
// sends each neighbour only these: a side neighbour one strip as long as the
// shared side, a corner neighbour one cell.
std::vector<std::size_t> ring_indices_facing(const MapGeometry& geo, const Rect& sender, const Rect& receiver);

class RegionField {
 public:
  RegionField(const MapGeometry& geo, RegionId region, const ShaoLayerParams& params);

  [[nodiscard]] const Rect& rect() const { return rect_; }
  [[nodiscard]] RegionId region() const { return region_; }
  // Row-major values over rect() for one layer.
  [[nodiscard]] std::span<const float> layer(Layer l) const;
  [[nodiscard]] float value(Layer l, Cell c) const;  // c must be in rect()
  // The values of layer l over r (inside rect()), row-major into out
  // (r.area() values), a row at a time.
  void copy_rect(Layer l, const Rect& r, float* out) const;
  // Direct write access, for tests and for restoring state. The next step
  // then updates every cell of the layer (it forgets which ones were +0), so
  // write through the span before that step's begin_step(), not after (a
  // call between begin_step() and finish_step() leaves that step's sources
  // as begin_step() took them, and its writes are overwritten, as ever).
  [[nodiscard]] std::span<float> mutable_layer(Layer l);

  // Deposit switches. kε(i)=1 once an obstacle at i is marked (stays on).
  void set_obstacle_switch(Cell c);
  // kτ(i)=1 while the target at i is due for a revisit.
  void set_target_switch(Cell c, bool on);
  [[nodiscard]] bool obstacle_switch(Cell c) const;
  [[nodiscard]] bool target_switch(Cell c) const;
  void set_target_state(Cell c, float state);  // TargetState layer value

  // A UAV is at `uav` after its move: accumulate Δσ^k_ij for every cell of this
  // region within D0 (Shao 2020 eq. (6), Shao 2020 eq. (7)). Applied at the next step().
  void add_path_visit(Cell uav);

  // 1) Computes the sources s = v + k·d for target and obstacle layers and
  //    returns this region's border ring of them (to publish to neighbours).
  HaloRing begin_step();
  // 2) Accepts a neighbour's ring (any region whose rect touches ours); cells
  //    of the ring that fall in our 1-cell halo are stored. Rings from regions
  //    that are not neighbours are ignored. Missing rings leave the last value
  //    (initially 0) in the halo.
  void accept_halo(const Rect& neighbour_rect, const HaloRing& ring);
  // 3) Applies Shao 2020 eq. (1), Shao 2020 eq. (2), Shao 2020 eq. (3),
  //    Shao 2020 eq. (4) to target and obstacle layers using the halo, and
  //    Shao 2020 eq. (5), Shao 2020 eq. (8) to the path layer with the visits
  //    accumulated since the last step; clears the visits.
  // A step costs what is not zero (issue 44): the cells of a layer whose
  // whole 3 x 3 neighbourhood of sources is +0 keep their +0 without being
  // computed (they would compute combine(+0, +0), which is +0 for the
  // papers' coefficients; for others every cell is computed), and the path
  // layer is updated only around the visits (σ − 0 clamped is σ again). The
  // bits are those of computing every cell.
  void finish_step();
  // Columns per chunk of the activity maps below.
  static constexpr std::size_t kChunkCells = 16;

 private:
  const MapGeometry* geo_;
  RegionId region_;
  ShaoLayerParams p_;
  Rect rect_;
  std::vector<float> layers_[kLayerCount];
  std::vector<uint8_t> k_tau_, k_eps_;
  std::vector<float> path_delta_;
  // (w+2) x (h+2) padded: the neighbours' sources in the halo cells (the
  // interior is not used: finish_step takes the own sources from the values
  // and switches), and the per-cell 1/|N(j)| weights.
  std::vector<float> src_tau_, src_eps_, inv_n_;
  // The padded row py of inv_n_ begins at inv_row_[py] (an equal earlier row if any).
  std::vector<std::size_t> inv_row_;
  // Per diffused layer (0 target, 1 obstacle): k·d per own cell (d where
  // the switch is on, +0 where it is off: what a source adds).
  std::vector<float> kd_[2];
  // Per diffused layer, one flag per row and chunk of kChunkCells columns:
  // active (a value or a k·d is not +0; 0 means neither).
  std::size_t chunks_ = 0;  // chunks per row
  std::vector<uint8_t> active_[2];
  std::vector<uint8_t> need_;        // scratch, per row and chunk: compute it this step
  std::vector<float> rows_;          // scratch: three padded rows of shares s / |N(j)|
  std::vector<uint8_t> wanted_;      // scratch, per chunk: the shares of a padded row to take
  bool sparse_[2] = {false, false};  // combine(+0, +0) is +0 for the layer's coefficients
  bool full_[2] = {true, true};      // compute every chunk at the next step (mutable_layer)
  // Between begin_step and finish_step: switches set then wait for the end
  // of the step, values written then (mutable_layer) are diffused from a
  // copy taken before them, as begin_step saw them.
  bool in_step_ = false;
  struct PendingSwitch {
    int which;
    Cell cell;
    std::size_t index;
    float kd;
  };
  std::vector<PendingSwitch> pending_kd_;
  std::vector<float> snapshot_[2];
  void set_kd(int which, Cell c, std::size_t i, float kd);
  // Path: the rects (local cells) visited since the last step; every cell
  // when path_full_ (the first step, mutable_layer).
  std::vector<Rect> path_visited_;
  bool path_full_ = true;
  // Shao 2020 eq. (7) per offset (dx, dy) in [-D0, D0]², row-major, when D0
  // is at most kPathTableReach cells (empty otherwise: computed per visit).
  static constexpr double kPathTableReach = 32.0;
  std::vector<double> path_table_;
  // Index of own cell c's chunk in active_ and sources_.
  [[nodiscard]] std::size_t chunk_of(Cell c) const {
    return static_cast<std::size_t>(c.y - rect_.y0) * chunks_ + static_cast<std::size_t>(c.x - rect_.x0) / kChunkCells;
  }
  // A diffused layer's step (0 target, 1 obstacle): which chunks of every
  // row to compute into need_ (true: all of them), the shares of padded row
  // py into rows_, and the step itself.
  bool mark_needed(int which);
  void weigh_row(int which, std::size_t py, bool all, const float* v);
  void diffuse(int which);
  // Row-major index of c in rect(), or nothing if c is outside it.
  [[nodiscard]] std::optional<std::size_t> own_index(Cell c) const;
};

// Reference: one step of Shao 2020 eq. (1), Shao 2020 eq. (2), Shao 2020 eq. (3), Shao 2020 eq. (4) on a whole undivided map, straight from
// the equations (used by tests and the benchmark as the baseline). `k` is the
// switch per cell; `a_evaporates_diffusion` selects Shao 2020 eq. (3) (true, obstacle:
// (1-E) multiplies the neighbour sum too) or Shao 2020 eq. (1) (false, target).
void reference_diffuse(const MapGeometry& geo, std::span<const float> in, std::span<const uint8_t> k, double e,
                       double g, double d, bool evaporate_neighbour_sum, std::span<float> out);

}  // namespace pheromesh::core
