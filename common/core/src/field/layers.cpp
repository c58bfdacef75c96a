// Shao 2020 semantic pheromone layers (Shao 2020 Sec. 4.1, Shao 2020 eq. (1), Shao 2020 eq. (2), Shao 2020 eq. (3), Shao 2020 eq. (4), Shao 2020 eq. (5), Shao 2020 eq. (6), Shao 2020 eq. (7), Shao 2020 eq. (8)) over one
// region with a one-cell halo, and the whole-map reference step.
//
// Exactness contract between reference_diffuse and RegionField: both compute,
// per cell i and in float,
//   s_j   = v_j + (k_j ? d : 0)                                 source
//   nb_i  = sum over the in-map 8-neighbours j of i, in the order
//           (-1,-1) (0,-1) (1,-1) (-1,0) (1,0) (-1,1) (0,1) (1,1), of
//           s_j * (1 / |N(j)|)
//   out_i = combine(s_i, nb_i)                                  Shao 2020 eq. (1) or Shao 2020 eq. (3)
// with the same helper functions below. RegionField adds +0 for out-of-map
// neighbours (source 0, weight 0) where the reference skips them; x + (+0) == x
// for every x except -0, which compares equal anyway. So the split map and the
// undivided map give bitwise-equal results as long as the compiler neither
// reassociates (no -ffast-math) nor fuses a multiply into an add (FMA
// contraction). Contraction would hit the two sides differently: the
// reference's `nb += s_j * inv` would fuse, RegionField's precomputed weights
// would not. GCC contracts by default in C++ whenever the target has FMA
// (e.g. -march=native), so it is switched off for this file below.
#include "pheromesh/core/layers.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstring>
#include <numbers>
#include <optional>

// After the includes, so only this file's functions are affected.
// The 8-lane vector helpers below are always inlined and file-local: the
// ABI note GCC gives for passing them by value without AVX does not apply.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
#if defined(__clang__)
#pragma clang fp contract(off)
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off")
#endif

namespace pheromesh::core {

namespace {

// Step coefficients, rounded to float once so both implementations use the same.
struct StepCoeffs {
  float d = 0.0F;     // deposit per iteration (dτ or dε)
  float g = 0.0F;     // G, multiplies the neighbour sum: g(i,t) = G * Σ s_j/|N(j)|, Shao 2020 eq. (2), Shao 2020 eq. (4)
  float self = 0.0F;  // Shao 2020 eq. (1): (1-E)(1-G);  Shao 2020 eq. (3): (1-G)
  float evap = 1.0F;  // Shao 2020 eq. (3): (1-E), applied to the whole brace; unused for Shao 2020 eq. (1)
};

StepCoeffs make_coeffs(double e, double g, double d, bool evaporate_neighbour_sum) {
  StepCoeffs c;
  c.d = static_cast<float>(d);
  c.g = static_cast<float>(g);
  c.self = evaporate_neighbour_sum ? static_cast<float>(1.0 - g) : static_cast<float>((1.0 - e) * (1.0 - g));
  c.evap = static_cast<float>(1.0 - e);
  return c;
}

// s = v + k·d, the quantity that stays and diffuses (brackets of Shao 2020 eq. (1), Shao 2020 eq. (2), Shao 2020 eq. (3), Shao 2020 eq. (4)).
inline float source(float v, uint8_t k, float d) { return v + (k != 0 ? d : 0.0F); }

// 1/|N(j)|; 0 for a cell with no neighbours (1x1 map), which then never
// appears in any N(i) anyway.
inline float inv_count(int32_t n) { return n > 0 ? 1.0F / static_cast<float>(n) : 0.0F; }

template <bool kEvaporateNeighbourSum>
inline float combine(float s, float nb, const StepCoeffs& c) {
  if constexpr (kEvaporateNeighbourSum) {
    return c.evap * (c.self * s + c.g * nb);  // Shao 2020 eq. (3): (1-E){(1-G)[ε+kd] + g}
  } else {
    return c.self * s + c.g * nb;  // Shao 2020 eq. (1): (1-E)(1-G)[τ+kd] + g
  }
}

// Lanes per block: the blocked loops below run in fixed blocks of 8 plus a
// scalar tail. Each lane is independent, so this does not change any per-cell
// operation order.
constexpr std::size_t kBlock = 8;

// The hot loops are compiled twice on x86-64 with GCC, for AVX2 and for the
// baseline, and the loader picks one for the CPU (an ifunc). AVX2 without FMA:
// the same IEEE float additions and multiplications in wider registers, so
// both clones give the same bits (and the contraction guard above holds for
// both).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define PHEROMESH_KERNEL __attribute__((target_clones("avx2", "default")))
#else
#define PHEROMESH_KERNEL
#endif
#define PHEROMESH_INLINE inline __attribute__((always_inline))

// Eight lanes written as GCC/Clang vector types rather than left to the
// auto-vectoriser, which at -O2 packs these loops two floats at a time: one
// AVX2 register in the AVX2 clone, two SSE registers in the baseline one.
// Lane-wise + and * are the scalar IEEE operations, in the order written.
typedef float F8 __attribute__((vector_size(32)));
typedef int32_t I8 __attribute__((vector_size(32)));

PHEROMESH_INLINE F8 load8(const float* p) {
  F8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
PHEROMESH_INLINE void store8(float* p, F8 v) { std::memcpy(p, &v, sizeof v); }
PHEROMESH_INLINE F8 splat8(float f) { return F8{f, f, f, f, f, f, f, f}; }

// (v + k·d) / |N(j)| for a run of n cells: the source of Shao 2020 eq. (1)
// or Shao 2020 eq. (3) and its share per neighbour, Shao 2020 eq. (2). kd holds
// k·d per cell as source() adds it: d where the switch is on, +0 where it is
// off.
PHEROMESH_KERNEL void weigh_sources(const float* __restrict v, const float* __restrict kd,
                                    const float* __restrict inv_n, float* __restrict weighted, std::size_t n) {
  std::size_t i = 0;
  for (; i + kBlock <= n; i += kBlock) store8(weighted + i, (load8(v + i) + load8(kd + i)) * load8(inv_n + i));
  for (; i < n; ++i) weighted[i] = (v[i] + kd[i]) * inv_n[i];
}

// s / |N(j)| for n halo cells, whose sources s came from the neighbours.
PHEROMESH_KERNEL void weigh_halo(const float* __restrict src, const float* __restrict inv_n, float* __restrict weighted,
                                 std::size_t n) {
  std::size_t i = 0;
  for (; i + kBlock <= n; i += kBlock) store8(weighted + i, load8(src + i) * load8(inv_n + i));
  for (; i < n; ++i) weighted[i] = src[i] * inv_n[i];
}

// The step coefficients in every lane, built once per run.
struct StepCoeffs8 {
  F8 self, g, evap;
  explicit StepCoeffs8(const StepCoeffs& c) : self(splat8(c.self)), g(splat8(c.g)), evap(splat8(c.evap)) {}
};

// Shao 2020 eq. (1) or Shao 2020 eq. (3) for eight cells from their weighted
// neighbour rows (u, m, d at the padded column left of the first cell).
template <bool kEvaporateNeighbourSum>
PHEROMESH_INLINE F8 combine8(const float* u, const float* m, const float* d, const float* v, const float* kd,
                             const StepCoeffs8& c) {
  // Same neighbour order as reference_diffuse; do not regroup.
  const F8 nb =
      load8(u) + load8(u + 1) + load8(u + 2) + load8(m) + load8(m + 2) + load8(d) + load8(d + 1) + load8(d + 2);
  const F8 s = load8(v) + load8(kd);  // source()
  if constexpr (kEvaporateNeighbourSum) {
    return c.evap * (c.self * s + c.g * nb);  // Shao 2020 eq. (3)
  } else {
    return c.self * s + c.g * nb;  // Shao 2020 eq. (1)
  }
}

// One output run of w cells that begins at a chunk (kChunk cells) of its row:
// up/mid/dn are the weighted padded rows above, at and below (pointing at the
// padded column left of the run's first cell), v the values and kd the
// switches' k·d of the run (their sum is the source), o the output, which may
// be v itself: each block of eight is read before it is written. active[i]
// is set to whether chunk i of the run holds a value or a k·d that is not +0.
constexpr std::size_t kChunk = RegionField::kChunkCells;
static_assert(kChunk == 2 * kBlock, "a chunk is two blocks");
template <bool kEvaporateNeighbourSum>
PHEROMESH_INLINE void diffuse_run(const float* __restrict up, const float* __restrict mid, const float* __restrict dn,
                                  const float* v, const float* __restrict kd, float* o, std::size_t w,
                                  const StepCoeffs coeffs, uint8_t* __restrict active) {
  const StepCoeffs c = coeffs;  // a local copy keeps the coefficients in registers
  const StepCoeffs8 c8(c);
  std::size_t x = 0;
  for (; x + kChunk <= w; x += kChunk) {
    const F8 a = combine8<kEvaporateNeighbourSum>(up + x, mid + x, dn + x, v + x, kd + x, c8);
    const std::size_t y = x + kBlock;
    const F8 b = combine8<kEvaporateNeighbourSum>(up + y, mid + y, dn + y, v + y, kd + y, c8);
    store8(o + x, a);
    store8(o + y, b);
    const I8 bits = std::bit_cast<I8>(a) | std::bit_cast<I8>(b) | std::bit_cast<I8>(load8(kd + x)) |
                    std::bit_cast<I8>(load8(kd + y));
    // A lane that is not 0 settles it (in a field that is not +0 the first
    // one nearly always does); else all eight are looked at.
    int32_t any = bits[0];
    if (any == 0) {
      for (std::size_t l = 1; l < kBlock; ++l) any |= bits[l];
    }
    active[x / kChunk] = any != 0 ? 1 : 0;
  }
  if (x < w) {  // the last chunk of a row that is not a whole one
    uint32_t any = 0;
    for (std::size_t i = x; i < w; ++i) {
      const float nb = up[i] + up[i + 1] + up[i + 2] + mid[i] + mid[i + 2] + dn[i] + dn[i + 1] + dn[i + 2];
      o[i] = combine<kEvaporateNeighbourSum>(v[i] + kd[i], nb, c);
      uint32_t b = 0;
      uint32_t bk = 0;
      std::memcpy(&b, o + i, sizeof b);
      std::memcpy(&bk, kd + i, sizeof bk);
      any |= b | bk;
    }
    active[x / kChunk] = any != 0 ? 1 : 0;
  }
}

// Shao 2020 eq. (1) with Shao 2020 eq. (2) (target) and Shao 2020 eq. (3)
// with Shao 2020 eq. (4) (obstacle), one clone each.
PHEROMESH_KERNEL void diffuse_target_run(const float* up, const float* mid, const float* dn, const float* v,
                                         const float* kd, float* o, std::size_t w, const StepCoeffs c,
                                         uint8_t* active) {
  diffuse_run<false>(up, mid, dn, v, kd, o, w, c, active);
}
PHEROMESH_KERNEL void diffuse_obstacle_run(const float* up, const float* mid, const float* dn, const float* v,
                                           const float* kd, float* o, std::size_t w, const StepCoeffs c,
                                           uint8_t* active) {
  diffuse_run<true>(up, mid, dn, v, kd, o, w, c, active);
}

// σ = clamp(σ − Δσ, σmin, σ0), Shao 2020 eq. (5) and Shao 2020 eq. (8); clears Δσ.
PHEROMESH_KERNEL void update_path(float* __restrict sigma, float* __restrict delta, std::size_t n, float lo, float hi) {
  std::size_t i = 0;
  for (; i + kBlock <= n; i += kBlock) {
    for (std::size_t l = 0; l < kBlock; ++l) {
      sigma[i + l] = std::min(std::max(sigma[i + l] - delta[i + l], lo), hi);
      delta[i + l] = 0.0F;
    }
  }
  for (; i < n; ++i) {
    sigma[i] = std::min(std::max(sigma[i] - delta[i], lo), hi);
    delta[i] = 0.0F;
  }
}

// Whether any of n floats is not +0 (the one float whose bits are all 0):
// -0, denormals and NaN count as non-zero.
bool any_nonzero_bits(const float* v, std::size_t n) {
  uint32_t acc = 0;
  for (std::size_t i = 0; i < n; ++i) {
    uint32_t b = 0;
    std::memcpy(&b, v + i, sizeof b);
    acc |= b;
  }
  return acc != 0;
}

bool is_positive_zero(float f) {
  uint32_t b = 1;
  std::memcpy(&b, &f, sizeof b);
  return b == 0;
}

// Index of cell (x, y) in the border ring of rect r (row-major over the border
// cells), or nothing if the cell is not on r's border. 64-bit so that a
// malformed rect from a peer cannot overflow.
std::optional<std::size_t> border_index(const Rect& r, int64_t x, int64_t y) {
  const int64_t w = r.w;
  const int64_t h = r.h;
  const int64_t dx = x - r.x0;
  const int64_t dy = y - r.y0;
  if (w <= 0 || h <= 0 || dx < 0 || dy < 0 || dx >= w || dy >= h) return std::nullopt;
  const int64_t per_middle_row = w >= 2 ? 2 : 1;  // border cells in a row that is not first or last
  if (dy == 0) return static_cast<std::size_t>(dx);
  if (dy == h - 1) return static_cast<std::size_t>(w + (h - 2) * per_middle_row + dx);
  const int64_t row_start = w + (dy - 1) * per_middle_row;
  if (dx == 0) return static_cast<std::size_t>(row_start);
  if (dx == w - 1) return static_cast<std::size_t>(row_start + per_middle_row - 1);
  return std::nullopt;
}

inline std::size_t layer_index(Layer l) {
  const auto i = static_cast<std::size_t>(l);
  assert(i < static_cast<std::size_t>(kLayerCount));
  return i;
}

}  // namespace

const char* layer_name(Layer l) {
  switch (l) {
    case Layer::Target:
      return "target";
    case Layer::Obstacle:
      return "obstacle";
    case Layer::Path:
      return "path";
    case Layer::TargetState:
      return "target_state";
  }
  return "unknown";
}

double path_decrease(double dist, const ShaoLayerParams& p) {
  // Shao 2020 eq. (7), as printed: the factor depends on (Q / D), not D / Q.
  if (!(dist <= p.d0)) return 0.0;         // D > D0 (or NaN): out of the UAV's influence
  if (dist <= 0.0) return 0.9 * p.sigma0;  // D == 0: the UAV's own cell decays fastest
  const double a = p.q / dist;
  return std::exp(-0.5 * a * a) / (2.0 * std::sqrt(2.0 * std::numbers::pi)) * p.sigma0;
}

std::optional<std::size_t> ring_index(const Rect& r, int64_t x, int64_t y) { return border_index(r, x, y); }

std::size_t ring_size(const Rect& r) {
  const int64_t w = r.w;
  const int64_t h = r.h;
  if (w <= 0 || h <= 0) return 0;
  if (h == 1) return static_cast<std::size_t>(w);
  const int64_t per_middle_row = w >= 2 ? 2 : 1;
  return static_cast<std::size_t>(2 * w + (h - 2) * per_middle_row);
}

std::vector<std::size_t> ring_indices_facing(const MapGeometry& geo, const Rect& sender, const Rect& receiver) {
  std::vector<std::size_t> out;
  const auto add = [&](int64_t x, int64_t y) {
    if (x < 0 || y < 0 || x >= geo.width() || y >= geo.height()) return;
    if (auto k = border_index(sender, x, y)) out.push_back(*k);
  };
  // The receiver's halo: the cells just outside its rect, walked as accept_halo walks them.
  const int64_t x0 = int64_t{receiver.x0} - 1, x1 = int64_t{receiver.x0} + receiver.w;
  const int64_t y0 = int64_t{receiver.y0} - 1, y1 = int64_t{receiver.y0} + receiver.h;
  for (int64_t x = x0; x <= x1; ++x) {
    add(x, y0);
    add(x, y1);
  }
  for (int64_t y = y0 + 1; y < y1; ++y) {
    add(x0, y);
    add(x1, y);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// ---------------------------------------------------------------------------
// RegionField
// ---------------------------------------------------------------------------

RegionField::RegionField(const MapGeometry& geo, RegionId region, const ShaoLayerParams& params)
    : geo_(&geo), region_(region), p_(params), rect_(geo.region_rect(region)) {
  assert(region < geo.region_count());
  const auto cells = static_cast<std::size_t>(rect_.area());
  layers_[layer_index(Layer::Target)].assign(cells, 0.0F);
  layers_[layer_index(Layer::Obstacle)].assign(cells, 0.0F);
  layers_[layer_index(Layer::Path)].assign(cells, static_cast<float>(p_.sigma0));  // path starts at σ0
  layers_[layer_index(Layer::TargetState)].assign(cells, kTargetUnknown);
  k_tau_.assign(cells, 0);
  k_eps_.assign(cells, 0);
  path_delta_.assign(cells, 0.0F);

  const auto pw = static_cast<std::size_t>(rect_.w) + 2;
  const auto ph = static_cast<std::size_t>(rect_.h) + 2;
  src_tau_.assign(pw * ph, 0.0F);
  src_eps_.assign(pw * ph, 0.0F);
  inv_n_.assign(pw * ph, 0.0F);
  chunks_ = (static_cast<std::size_t>(rect_.w) + kChunkCells - 1) / kChunkCells;
  need_.assign(static_cast<std::size_t>(rect_.h) * chunks_, 0);
  rows_.assign(3 * pw, 0.0F);
  wanted_.assign(chunks_, 0);
  for (int which = 0; which < 2; ++which) {
    kd_[which].assign(cells, 0.0F);
    active_[which].assign(static_cast<std::size_t>(rect_.h) * chunks_, 0);
  }
  // A cell whose neighbourhood holds only +0 sources computes
  // combine(+0, +0): skipped only where that is +0 again (E, G in [0, 1]).
  sparse_[0] = is_positive_zero(combine<false>(0.0F, 0.0F, make_coeffs(p_.e_tau, p_.g_tau, p_.d_tau, false)));
  sparse_[1] = is_positive_zero(combine<true>(0.0F, 0.0F, make_coeffs(p_.e_eps, p_.g_eps, p_.d_eps, true)));
  // 1/|N(j)| from the whole map (a region border is not a map border); 0 for
  // halo cells outside the map, so they never contribute.
  for (std::size_t py = 0; py < ph; ++py) {
    for (std::size_t px = 0; px < pw; ++px) {
      const Cell c{rect_.x0 - 1 + static_cast<int32_t>(px), rect_.y0 - 1 + static_cast<int32_t>(py)};
      if (geo.in_map(c)) inv_n_[py * pw + px] = inv_count(geo.neighbour_count(c));
    }
  }
  // Shao 2020 eq. (7) for every offset a visit reaches, once (the same
  // doubles add_path_visit would compute), when the square is small.
  if (p_.d0 >= 0.0 && p_.d0 <= kPathTableReach) {
    const auto reach = static_cast<int64_t>(std::floor(p_.d0));
    for (int64_t dy = -reach; dy <= reach; ++dy) {
      for (int64_t dx = -reach; dx <= reach; ++dx) {
        path_table_.push_back(path_decrease(std::sqrt(static_cast<double>(dx * dx + dy * dy)), p_));
      }
    }
  }
  // Most padded rows have the weights of row 1 or 2 (a map edge, the
  // interior): read those, which stay in the first-level cache.
  inv_row_.resize(ph);
  for (std::size_t py = 0; py < ph; ++py) {
    inv_row_[py] = py * pw;
    for (const std::size_t q : {std::size_t{1}, std::size_t{2}}) {
      if (q < py && std::equal(inv_n_.begin() + static_cast<std::ptrdiff_t>(py * pw),
                               inv_n_.begin() + static_cast<std::ptrdiff_t>((py + 1) * pw),
                               inv_n_.begin() + static_cast<std::ptrdiff_t>(q * pw))) {
        inv_row_[py] = q * pw;
        break;
      }
    }
  }
}

std::optional<std::size_t> RegionField::own_index(Cell c) const {
  if (!rect_.contains(c)) return std::nullopt;
  return static_cast<std::size_t>(c.y - rect_.y0) * static_cast<std::size_t>(rect_.w) +
         static_cast<std::size_t>(c.x - rect_.x0);
}

std::span<const float> RegionField::layer(Layer l) const { return layers_[layer_index(l)]; }

std::span<float> RegionField::mutable_layer(Layer l) {
  // What was +0 may not be any more: the next step computes every cell.
  if (l == Layer::Target || l == Layer::Obstacle) {
    const int which = l == Layer::Target ? 0 : 1;
    full_[which] = true;
    // Between begin_step and finish_step the step diffuses the sources of
    // begin_step: keep the values they come from.
    if (in_step_ && snapshot_[which].empty()) snapshot_[which] = layers_[layer_index(l)];
  }
  if (l == Layer::Path) path_full_ = true;
  return layers_[layer_index(l)];
}

float RegionField::value(Layer l, Cell c) const {
  const auto i = own_index(c);
  assert(i.has_value());
  return i ? layers_[layer_index(l)][*i] : 0.0F;
}

void RegionField::copy_rect(Layer l, const Rect& r, float* out) const {
  assert(r.w >= 0 && r.h >= 0 && rect_.contains({r.x0, r.y0}) && rect_.contains({r.x0 + r.w - 1, r.y0 + r.h - 1}));
  const std::vector<float>& v = layers_[layer_index(l)];
  const auto w = static_cast<std::size_t>(r.w);
  for (int32_t y = r.y0; y < r.y0 + r.h; ++y) {
    const auto from = static_cast<std::size_t>(y - rect_.y0) * static_cast<std::size_t>(rect_.w) +
                      static_cast<std::size_t>(r.x0 - rect_.x0);
    std::copy_n(v.data() + from, w, out);
    out += w;
  }
}

// Cells outside rect() are ignored by the setters: they may come from a peer.
void RegionField::set_obstacle_switch(Cell c) {
  if (const auto i = own_index(c)) {
    k_eps_[*i] = 1;
    set_kd(1, c, *i, static_cast<float>(p_.d_eps));
  }
}

void RegionField::set_target_switch(Cell c, bool on) {
  if (const auto i = own_index(c)) {
    k_tau_[*i] = on ? 1 : 0;
    set_kd(0, c, *i, on ? static_cast<float>(p_.d_tau) : 0.0F);
  }
}

void RegionField::set_kd(int which, Cell c, std::size_t i, float kd) {
  // Between begin_step and finish_step the step diffuses the sources of
  // begin_step: the switch joins them after it.
  if (in_step_) {
    pending_kd_.push_back({which, c, i, kd});
    return;
  }
  kd_[which][i] = kd;
  // Switched off, the chunk stays active until a step finds it all +0.
  active_[which][chunk_of(c)] = 1;
}

bool RegionField::obstacle_switch(Cell c) const {
  const auto i = own_index(c);
  return i && k_eps_[*i] != 0;
}

bool RegionField::target_switch(Cell c) const {
  const auto i = own_index(c);
  return i && k_tau_[*i] != 0;
}

void RegionField::set_target_state(Cell c, float state) {
  if (const auto i = own_index(c)) layers_[layer_index(Layer::TargetState)][*i] = state;
}

void RegionField::add_path_visit(Cell uav) {
  if (rect_.w <= 0 || rect_.h <= 0 || !(p_.d0 >= 0.0)) return;
  // Cells within D0 [cell] lie in the square of half-side floor(D0) around the UAV.
  const auto reach = static_cast<int64_t>(std::floor(std::min(p_.d0, 1.0e9)));
  const int64_t x_lo = std::max<int64_t>(int64_t{uav.x} - reach, rect_.x0);
  const int64_t x_hi = std::min<int64_t>(int64_t{uav.x} + reach, int64_t{rect_.x0} + rect_.w - 1);
  const int64_t y_lo = std::max<int64_t>(int64_t{uav.y} - reach, rect_.y0);
  const int64_t y_hi = std::min<int64_t>(int64_t{uav.y} + reach, int64_t{rect_.y0} + rect_.h - 1);
  if (x_lo > x_hi || y_lo > y_hi) return;
  // The next step updates σ inside this square only: elsewhere Δσ is 0.
  path_visited_.push_back({static_cast<int32_t>(x_lo - rect_.x0), static_cast<int32_t>(y_lo - rect_.y0),
                           static_cast<int32_t>(x_hi - x_lo + 1), static_cast<int32_t>(y_hi - y_lo + 1)});
  const bool table = !path_table_.empty();
  const auto side = static_cast<std::size_t>(2 * reach + 1);
  for (int64_t y = y_lo; y <= y_hi; ++y) {
    for (int64_t x = x_lo; x <= x_hi; ++x) {
      const int64_t dx = x - uav.x;
      const int64_t dy = y - uav.y;
      double delta = 0.0;
      if (table) {
        delta = path_table_[static_cast<std::size_t>(dy + reach) * side + static_cast<std::size_t>(dx + reach)];
      } else {
        const double dist = std::sqrt(static_cast<double>(dx * dx + dy * dy));  // D_ij [cell]
        delta = path_decrease(dist, p_);                                        // Shao 2020 eq. (7)
      }
      if (delta == 0.0) continue;
      const auto i = static_cast<std::size_t>(y - rect_.y0) * static_cast<std::size_t>(rect_.w) +
                     static_cast<std::size_t>(x - rect_.x0);
      path_delta_[i] += static_cast<float>(delta);  // Shao 2020 eq. (6): sum over UAVs k
    }
  }
}

HaloRing RegionField::begin_step() {
  const auto w = static_cast<std::size_t>(rect_.w);
  const auto h = static_cast<std::size_t>(rect_.h);
  for (int which = 0; which < 2; ++which) {
    if (full_[which]) std::fill(active_[which].begin(), active_[which].end(), uint8_t{1});
  }
  in_step_ = true;
  // The sources s = v + k·d of Shao 2020 eq. (1) and Shao 2020 eq. (3) on the
  // border, for the neighbours' halos. finish_step takes the others from the
  // same values and switches, which do not change before it.
  HaloRing ring;
  ring.region = region_;
  const std::size_t n = ring_size(rect_);
  ring.target.resize(n);
  ring.obstacle.resize(n);
  const float* tau = layers_[layer_index(Layer::Target)].data();
  const float* eps = layers_[layer_index(Layer::Obstacle)].data();
  const float* kd_tau = kd_[0].data();
  const float* kd_eps = kd_[1].data();
  std::size_t k = 0;
  const auto put = [&](std::size_t x, std::size_t y) {
    const std::size_t i = y * w + x;
    ring.target[k] = tau[i] + kd_tau[i];
    ring.obstacle[k] = eps[i] + kd_eps[i];
    ++k;
  };
  for_each_ring_cell(w, h, put);
  assert(k == n);
  return ring;
}

void RegionField::accept_halo(const Rect& neighbour_rect, const HaloRing& ring) {
  const std::size_t n = ring_size(neighbour_rect);
  if (n == 0 || ring.target.size() != n || ring.obstacle.size() != n) return;  // malformed: ignore
  const int64_t pw = int64_t{rect_.w} + 2;
  const int64_t ph = int64_t{rect_.h} + 2;
  // Walk our own halo (the padded cells outside rect()), not the neighbour's
  // ring: bounded by our size whatever the peer sent.
  const auto take = [&](int64_t px, int64_t py) {
    const int64_t x = int64_t{rect_.x0} - 1 + px;
    const int64_t y = int64_t{rect_.y0} - 1 + py;
    if (x < 0 || y < 0 || x >= geo_->width() || y >= geo_->height()) return;  // off the map: stays 0
    const auto k = border_index(neighbour_rect, x, y);
    if (!k) return;
    const auto p = static_cast<std::size_t>(py * pw + px);
    src_tau_[p] = ring.target[*k];
    src_eps_[p] = ring.obstacle[*k];
  };
  // Only the part of our halo inside the neighbour's rect can be on its border.
  const int64_t px_lo = std::max<int64_t>(int64_t{neighbour_rect.x0} - rect_.x0 + 1, 0);
  const int64_t px_hi = std::min<int64_t>(int64_t{neighbour_rect.x0} + neighbour_rect.w - rect_.x0 + 1, pw);
  const int64_t py_lo = std::max<int64_t>(int64_t{neighbour_rect.y0} - rect_.y0 + 1, 0);
  const int64_t py_hi = std::min<int64_t>(int64_t{neighbour_rect.y0} + neighbour_rect.h - rect_.y0 + 1, ph);
  if (px_lo >= px_hi || py_lo >= py_hi) return;
  for (const int64_t py : {int64_t{0}, ph - 1}) {
    if (py < py_lo || py >= py_hi) continue;
    for (int64_t px = px_lo; px < px_hi; ++px) take(px, py);
  }
  for (const int64_t px : {int64_t{0}, pw - 1}) {
    if (px < px_lo || px >= px_hi) continue;
    for (int64_t py = std::max<int64_t>(py_lo, 1); py < std::min<int64_t>(py_hi, ph - 1); ++py) take(px, py);
  }
}

namespace {

// Calls f(begin, end) for each maximal run [begin, end) of non-zero flags.
template <typename F>
void for_each_run(const uint8_t* flags, std::size_t n, F&& f) {
  for (std::size_t i = 0; i < n;) {
    if (flags[i] == 0) {
      ++i;
      continue;
    }
    std::size_t e = i + 1;
    while (e < n && flags[e] != 0) ++e;
    f(i, e);
    i = e;
  }
}

}  // namespace

bool RegionField::mark_needed(int which) {
  const auto w = static_cast<std::size_t>(rect_.w);
  const auto h = static_cast<std::size_t>(rect_.h);
  const std::size_t pw = w + 2;
  const std::size_t ph = h + 2;
  const float* halo = which == 0 ? src_tau_.data() : src_eps_.data();
  const uint8_t* act = active_[which].data();
  // Every chunk after mutable_layer, for coefficients that turn +0 into
  // something else, and when every chunk is active anyway.
  const bool all =
      full_[which] || !sparse_[which] || std::find(act, act + h * chunks_, uint8_t{0}) == act + h * chunks_;
  if (all) {
    std::fill(need_.begin(), need_.end(), uint8_t{1});
    return true;
  }
  for (std::size_t y = 0; y < h; ++y) {
    uint8_t* need = need_.data() + y * chunks_;
    // The rows above, at and below, then a chunk to each side.
    const uint8_t* above = act + (y == 0 ? y : y - 1) * chunks_;
    const uint8_t* at = act + y * chunks_;
    const uint8_t* below = act + std::min(y + 1, h - 1) * chunks_;
    uint8_t left = 0;
    uint8_t here = above[0] | at[0] | below[0];
    for (std::size_t i = 0; i < chunks_; ++i) {
      const uint8_t right = i + 1 < chunks_ ? static_cast<uint8_t>(above[i + 1] | at[i + 1] | below[i + 1]) : 0;
      need[i] = static_cast<uint8_t>(left | here | right);
      left = here;
      here = right;
    }
    for (const std::size_t py : {std::size_t{0}, ph - 1}) {  // the halo row above the first row, below the last
      if ((py == 0 && y != 0) || (py == ph - 1 && y + 1 != h)) continue;
      for (std::size_t i = 0; i < chunks_; ++i) {
        const std::size_t x0 = i * kChunkCells;
        const std::size_t x1 = std::min(x0 + kChunkCells, w) + 2;
        if (any_nonzero_bits(halo + py * pw + x0, x1 - x0)) need[i] = 1;
      }
    }
    for (std::size_t py = y; py < y + 3; ++py) {  // the halo columns left and right
      if (any_nonzero_bits(halo + py * pw, 1)) need[0] = 1;
      if (any_nonzero_bits(halo + py * pw + pw - 1, 1)) need[chunks_ - 1] = 1;
    }
  }
  return false;
}

void RegionField::weigh_row(int which, std::size_t py, bool all, const float* v) {
  const auto w = static_cast<std::size_t>(rect_.w);
  const auto h = static_cast<std::size_t>(rect_.h);
  const std::size_t pw = w + 2;
  const std::size_t ph = h + 2;
  const float* kd = kd_[which].data();
  float* dst = rows_.data() + (py % 3) * pw;
  const float* inv = inv_n_.data() + inv_row_[py];
  const float* hrow = (which == 0 ? src_tau_.data() : src_eps_.data()) + py * pw;
  // The chunks the rows py - 2 .. py need.
  uint8_t* wanted = wanted_.data();
  std::fill(wanted, wanted + chunks_, static_cast<uint8_t>(all ? 1 : 0));
  for (std::size_t y = py < 2 ? 0 : py - 2; !all && y <= std::min(py, h - 1); ++y) {
    const uint8_t* need = need_.data() + y * chunks_;
    for (std::size_t k = 0; k < chunks_; ++k) wanted[k] = static_cast<uint8_t>(wanted[k] | need[k]);
  }
  for_each_run(wanted, chunks_, [&](std::size_t i, std::size_t e) {
    const std::size_t px0 = i * kChunkCells;  // padded columns [px0, px1)
    const std::size_t px1 = std::min(e * kChunkCells, w) + 2;
    if (py == 0 || py + 1 == ph) {  // a halo row
      weigh_halo(hrow + px0, inv + px0, dst + px0, px1 - px0);
      return;
    }
    const std::size_t in0 = std::max<std::size_t>(px0, 1);  // own columns [in0, in1)
    const std::size_t in1 = std::min(px1, pw - 1);
    if (px0 == 0) dst[0] = hrow[0] * inv[0];
    const std::size_t row = (py - 1) * w;
    weigh_sources(v + row + in0 - 1, kd + row + in0 - 1, inv + in0, dst + in0, in1 - in0);
    if (px1 == pw) dst[pw - 1] = hrow[pw - 1] * inv[pw - 1];
  });
}

void RegionField::diffuse(int which) {
  const auto w = static_cast<std::size_t>(rect_.w);
  const auto h = static_cast<std::size_t>(rect_.h);
  const std::size_t pw = w + 2;
  const bool target = which == 0;
  const StepCoeffs c =
      target ? make_coeffs(p_.e_tau, p_.g_tau, p_.d_tau, false) : make_coeffs(p_.e_eps, p_.g_eps, p_.d_eps, true);
  const float* kd = kd_[which].data();
  float* out = layers_[layer_index(target ? Layer::Target : Layer::Obstacle)].data();
  // The values of begin_step (the same array unless mutable_layer was called since).
  const float* v = snapshot_[which].empty() ? out : snapshot_[which].data();
  uint8_t* act = active_[which].data();
  // Which chunks of every row to compute, from the activity of begin_step
  // (act is rewritten row by row below).
  const bool all = mark_needed(which);
  // Row y needs the shares of padded rows y, y + 1, y + 2, and its own
  // values before it overwrites them: the shares of the row below it are
  // taken first.
  weigh_row(which, 0, all, v);
  weigh_row(which, 1, all, v);
  for (std::size_t y = 0; y < h; ++y) {
    weigh_row(which, y + 2, all, v);
    // Chunks left out have only +0 sources around: their cells stay +0 (sparse_).
    for_each_run(need_.data() + y * chunks_, chunks_, [&](std::size_t i, std::size_t e) {
      const std::size_t x0 = i * kChunkCells;
      const std::size_t x1 = std::min(e * kChunkCells, w);
      const float* up = rows_.data() + (y % 3) * pw + x0;
      const float* mid = rows_.data() + ((y + 1) % 3) * pw + x0;
      const float* dn = rows_.data() + ((y + 2) % 3) * pw + x0;
      const std::size_t a = y * w + x0;
      uint8_t* flags = act + y * chunks_ + i;
      if (target) {
        diffuse_target_run(up, mid, dn, v + a, kd + a, out + a, x1 - x0, c, flags);  // Shao 2020 eq. (1)
      } else {
        diffuse_obstacle_run(up, mid, dn, v + a, kd + a, out + a, x1 - x0, c, flags);  // Shao 2020 eq. (3)
      }
    });
  }
  full_[which] = false;
  snapshot_[which].clear();
}

void RegionField::finish_step() {
  if (rect_.w <= 0 || rect_.h <= 0) return;
  diffuse(0);  // Shao 2020 eq. (1), Shao 2020 eq. (2)
  diffuse(1);  // Shao 2020 eq. (3), Shao 2020 eq. (4)
  in_step_ = false;
  for (const PendingSwitch& sw : pending_kd_) set_kd(sw.which, sw.cell, sw.index, sw.kd);
  pending_kd_.clear();

  // Path: σ(t+1) = σ(t) − Δσ(t), Shao 2020 eq. (5), clamped into [σmin, σ0],
  // Shao 2020 eq. (8). Where Δσ is 0 a clamped σ stays what it is, so only
  // the visited squares are updated (every cell once after mutable_layer).
  const float lo = static_cast<float>(p_.sigma_min);
  const float hi = static_cast<float>(p_.sigma0);
  float* sigma = layers_[layer_index(Layer::Path)].data();
  const auto w = static_cast<std::size_t>(rect_.w);
  if (path_full_) {
    update_path(sigma, path_delta_.data(), w * static_cast<std::size_t>(rect_.h), lo, hi);
    path_full_ = false;
  } else {
    // A cell in two squares is clamped twice: the second time with Δσ = 0,
    // which leaves it as it is.
    for (const Rect& r : path_visited_) {
      for (int32_t y = r.y0; y < r.y0 + r.h; ++y) {
        const std::size_t a = static_cast<std::size_t>(y) * w + static_cast<std::size_t>(r.x0);
        update_path(sigma + a, path_delta_.data() + a, static_cast<std::size_t>(r.w), lo, hi);
      }
    }
  }
  path_visited_.clear();
}

// ---------------------------------------------------------------------------
// Reference
// ---------------------------------------------------------------------------

void reference_diffuse(const MapGeometry& geo, std::span<const float> in, std::span<const uint8_t> k, double e,
                       double g, double d, bool evaporate_neighbour_sum, std::span<float> out) {
  const auto cells = static_cast<std::size_t>(geo.map_rect().area());
  assert(in.size() == cells && k.size() == cells && out.size() == cells);
  assert(in.data() != out.data());  // out must not alias in
  if (in.size() != cells || k.size() != cells || out.size() != cells) return;
  const StepCoeffs c = make_coeffs(e, g, d, evaporate_neighbour_sum);
  for (int32_t y = 0; y < geo.height(); ++y) {
    for (int32_t x = 0; x < geo.width(); ++x) {
      const Cell ci{x, y};
      // g(i,t) / G = Σ_{j∈N(i)} s_j / |N(j)|, Shao 2020 eq. (2), Shao 2020 eq. (4); |N(j)| counted on the spot.
      float nb = 0.0F;
      for (int32_t dy = -1; dy <= 1; ++dy) {
        for (int32_t dx = -1; dx <= 1; ++dx) {
          const Cell cj{x + dx, y + dy};
          if ((dx == 0 && dy == 0) || !geo.in_map(cj)) continue;
          const std::size_t j = geo.index(cj);
          nb += source(in[j], k[j], c.d) * inv_count(geo.neighbour_count(cj));
        }
      }
      const std::size_t i = geo.index(ci);
      const float s = source(in[i], k[i], c.d);
      out[i] = evaporate_neighbour_sum ? combine<true>(s, nb, c) : combine<false>(s, nb, c);
    }
  }
}

}  // namespace pheromesh::core
