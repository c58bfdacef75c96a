// Declared layers (declared_layers.hpp): LayerAdd deposits, evaporation and
// diffusion with a one-cell halo, for policies that declare their layers.
#include "pheromesh/core/declared_layers.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/messages.hpp"

namespace pheromesh::core {
namespace {

std::string layer_label(std::size_t i, const LayerSpec& l) {
  return "layer " + std::to_string(i) + " ('" + l.name + "')";
}

class DeclaredLayersPlace final : public PlaceModel {
 public:
  DeclaredLayersPlace(std::vector<LayerSpec> layers, const MapGeometry& geo, RegionId region)
      : specs_(std::move(layers)), geo_(&geo), rect_(geo.region_rect(region)), region_(region) {
    const auto cells = static_cast<std::size_t>(rect_.area());
    pw_ = static_cast<std::size_t>(rect_.w) + 2;
    const std::size_t padded = pw_ * (static_cast<std::size_t>(rect_.h) + 2);
    values_.assign(specs_.size(), std::vector<float>(cells, 0.0F));
    for (std::size_t l = 0; l < specs_.size(); ++l) {
      if (specs_[l].diffusion > 0.0) diffusing_.push_back(l);
    }
    padded_.assign(diffusing_.size(), std::vector<float>(padded, 0.0F));
    // 1/|N(j)| of the whole map (a region's border is not the map's); 0 off
    // the map, so a halo cell there hands nothing.
    inv_n_.assign(padded, 0.0F);
    for (std::size_t py = 0; py < padded / pw_; ++py) {
      for (std::size_t px = 0; px < pw_; ++px) {
        const Cell c{rect_.x0 - 1 + static_cast<int32_t>(px), rect_.y0 - 1 + static_cast<int32_t>(py)};
        if (geo.in_map(c)) inv_n_[py * pw_ + px] = 1.0F / static_cast<float>(std::max(geo.neighbour_count(c), 1));
      }
    }
  }

  std::optional<std::string> apply(const DepositMsg& d, uint32_t /*tick*/,
                                   std::vector<TargetEventMsg>& /*events*/) override {
    if (static_cast<DepositKind>(d.kind) != DepositKind::LayerAdd) {
      return "deposit kind " + std::to_string(d.kind) + " is not used by declared layers (only LayerAdd, 3)";
    }
    if (d.layer >= specs_.size()) return "unknown layer " + std::to_string(d.layer);
    if (!rect_.contains(d.cell)) return std::string("cell outside the region");
    if (!std::isfinite(d.amount) || d.amount < 0.0F) return std::string("amount must be finite and >= 0");
    float& v = values_[d.layer][index(d.cell)];
    v = std::min(v + d.amount, specs_[d.layer].max);
    return std::nullopt;
  }

  HaloRing begin_step(uint32_t /*tick*/, std::vector<TargetEventMsg>& /*events*/) override {
    if (diffusing_.empty()) return {};
    const auto w = static_cast<std::size_t>(rect_.w);
    const auto h = static_cast<std::size_t>(rect_.h);
    // The interior of each padded buffer: the layer now; the halo keeps what
    // the neighbours sent last.
    for (std::size_t k = 0; k < diffusing_.size(); ++k) {
      const std::vector<float>& v = values_[diffusing_[k]];
      for (std::size_t y = 0; y < h; ++y) {
        std::copy_n(v.data() + y * w, w, padded_[k].data() + (y + 1) * pw_ + 1);
      }
    }
    HaloRing ring;
    ring.region = region_;
    const std::size_t n = ring_size(rect_);
    ring.target.reserve(n);
    ring.obstacle.reserve(n);
    const auto push = [&](std::size_t x, std::size_t y) {
      const std::size_t p = (y + 1) * pw_ + (x + 1);
      ring.target.push_back(padded_[0][p]);
      ring.obstacle.push_back(diffusing_.size() > 1 ? padded_[1][p] : 0.0F);
    };
    for_each_ring_cell(w, h, push);
    return ring;
  }

  void accept_halo(const Rect& neighbour_rect, const HaloRing& ring) override {
    if (diffusing_.empty()) return;
    const std::size_t n = ring_size(neighbour_rect);
    if (n == 0 || ring.target.size() != n || ring.obstacle.size() != n) return;  // malformed: ignore
    const auto pw = static_cast<int64_t>(pw_);
    const int64_t ph = int64_t{rect_.h} + 2;
    // Our own halo walked, not the neighbour's ring: bounded by our size.
    const auto take = [&](int64_t px, int64_t py) {
      const int64_t x = int64_t{rect_.x0} - 1 + px;
      const int64_t y = int64_t{rect_.y0} - 1 + py;
      if (x < 0 || y < 0 || x >= geo_->width() || y >= geo_->height()) return;
      const auto k = ring_index(neighbour_rect, x, y);
      if (!k) return;
      const auto p = static_cast<std::size_t>(py * pw + px);
      padded_[0][p] = ring.target[*k];
      if (diffusing_.size() > 1) padded_[1][p] = ring.obstacle[*k];
    };
    for (int64_t px = 0; px < pw; ++px) {
      take(px, 0);
      take(px, ph - 1);
    }
    for (int64_t py = 1; py + 1 < ph; ++py) {
      take(0, py);
      take(pw - 1, py);
    }
  }

  void finish_step() override {
    std::size_t k = 0;
    for (std::size_t l = 0; l < specs_.size(); ++l) {
      const auto keep = static_cast<float>(1.0 - specs_[l].evaporation);
      std::vector<float>& v = values_[l];
      if (k < diffusing_.size() && diffusing_[k] == l) {
        diffuse(padded_[k], static_cast<float>(specs_[l].diffusion), keep, specs_[l].max, v);
        ++k;
      } else {
        for (float& x : v) x *= keep;
      }
    }
  }

  [[nodiscard]] float value(int layer, Cell c) const override {
    return values_[static_cast<std::size_t>(layer)][index(c)];
  }

 private:
  [[nodiscard]] std::size_t index(Cell c) const {
    return static_cast<std::size_t>(c.y - rect_.y0) * static_cast<std::size_t>(rect_.w) +
           static_cast<std::size_t>(c.x - rect_.x0);
  }

  // v'(i) = keep · ((1 - g) · v(i) + g · Σ_j v(j) / |N(j)|), the neighbours
  // summed in one fixed order so that every split of the map adds the same
  // floats in the same order.
  // Capped at the layer's max: near the map's edge a cell's neighbours hand
  // it shares of 1/|N(j)| > 1/8, which can sum above max, and a value
  // outside the declared range would be refused as implausible.
  void diffuse(const std::vector<float>& src, float g, float keep, float max, std::vector<float>& out) const {
    const auto w = static_cast<std::size_t>(rect_.w);
    const auto h = static_cast<std::size_t>(rect_.h);
    const float stay = 1.0F - g;
    for (std::size_t y = 0; y < h; ++y) {
      for (std::size_t x = 0; x < w; ++x) {
        const std::size_t p = (y + 1) * pw_ + (x + 1);
        float sum = 0.0F;
        for (const std::size_t row : {p - pw_, p, p + pw_}) {
          for (const std::size_t q : {row - 1, row, row + 1}) {
            if (q != p) sum += src[q] * inv_n_[q];
          }
        }
        out[y * w + x] = std::min(keep * (stay * src[p] + g * sum), max);
      }
    }
  }

  std::vector<LayerSpec> specs_;
  const MapGeometry* geo_;
  Rect rect_;
  RegionId region_;
  std::size_t pw_ = 0;
  std::vector<std::vector<float>> values_;  // per layer, row-major over rect_
  std::vector<std::size_t> diffusing_;       // the layers that diffuse, in order (ring target, obstacle)
  std::vector<std::vector<float>> padded_;   // per diffusing layer: (w+2) x (h+2), with the halo
  std::vector<float> inv_n_;                 // 1/|N(j)| over the padded area
};

}  // namespace

Result<bool> check_layer_specs(std::span<const LayerSpec> layers) {
  if (layers.empty()) return Error{"a policy declares at least one layer"};
  if (layers.size() > 255) return Error{"at most 255 layers (a deposit names its layer in one byte)"};
  std::size_t diffusing = 0;
  for (std::size_t i = 0; i < layers.size(); ++i) {
    const LayerSpec& l = layers[i];
    if (l.name.empty()) return Error{"layer " + std::to_string(i) + " has no name"};
    if (!(l.evaporation >= 0.0 && l.evaporation < 1.0)) {
      return Error{layer_label(i, l) + ": evaporation must be in [0, 1) (got " + std::to_string(l.evaporation) + ")"};
    }
    if (!(l.diffusion >= 0.0 && l.diffusion < 1.0)) {
      return Error{layer_label(i, l) + ": diffusion must be in [0, 1) (got " + std::to_string(l.diffusion) + ")"};
    }
    if (!(l.max > 0.0F && l.max <= kMaxLayerValue)) {
      return Error{layer_label(i, l) + ": max must be in (0, " + std::to_string(kMaxLayerValue) + "] (got " +
                   std::to_string(l.max) + ")"};
    }
    diffusing += l.diffusion > 0.0 ? 1 : 0;
  }
  if (diffusing > kMaxDiffusingLayers) {
    return Error{std::to_string(diffusing) + " layers diffuse; at most " + std::to_string(kMaxDiffusingLayers) +
                 " can (a region sends its neighbours two layers' border cells)"};
  }
  return true;
}

void declare_layers(PolicyTraits& traits, std::span<const LayerSpec> layers) {
  traits.layers.clear();
  traits.layer_ranges.clear();
  for (const LayerSpec& l : layers) {
    traits.layers.push_back(l.name);
    traits.layer_ranges.push_back(ValueRange{0.0F, l.max});
  }
}

std::unique_ptr<PlaceModel> make_declared_layers_place(std::vector<LayerSpec> layers, const MapGeometry& geo,
                                                       RegionId region) {
  if (auto ok = check_layer_specs(layers); !ok) throw std::invalid_argument(ok.error().message);
  return std::make_unique<DeclaredLayersPlace>(std::move(layers), geo, region);
}

}  // namespace pheromesh::core
