// Liu 2022 (ESUSTPM) as a distributed policy (docs/policies/liu.md).
//  * Place agents own the target probability map: layer "tpm" starts at the
//    prior (Liu 2022 eq. (1), Liu 2022 eq. (2) over the whole map, the region's part kept), every
//    Observation deposit applies Liu 2022 eq. (4) (detection) or Liu 2022 eq. (5) (miss) to its
//    cell, "visited" marks the cells some UAV has been in, "confirmed" latches
//    P > θ (Liu 2022 Sec. 2.4) and emits a FirstMarked target event. No diffusion, no
//    evaporation: the paper has neither (Liu 2022 eq. (3), an unsearched cell keeps its
//    value).
//  * A UAV decides, once per tick (= one time cycle), a velocity from its own
//    state, the UAVs it can see (view.neighbours) and the TPM of the eight
//    cells around it (its tiles): ESUSTPM Liu 2022 eq. (6), Liu 2022 eq. (7), Liu 2022 eq. (8), Liu 2022 eq. (9) or a
//    Liu 2022 Sec. 5.1 baseline. It then flies the cycle in Δt steps (Liu 2022 eq. (10), Liu 2022 eq. (11), reflected
//    at the border) and sends one Observation per cell it enters, to the region owning it.
// The loop is that of run_liu_swarm (liu/src/swarm.cpp); the differences are
// listed in docs/policies/liu.md.
#include <algorithm>
#include <cmath>
#include <limits>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/rng.hpp"
#include "pheromesh/liu/policy.hpp"
#include "pheromesh/liu/swarm.hpp"
#include "pheromesh/liu/tpm.hpp"

namespace pheromesh::core {

namespace {

enum LiuLayer : int { kTpm = 0, kVisited = 1, kConfirmed = 2, kLiuLayerCount = 3 };
constexpr uint8_t kFirstMarked = 0;  // MarkEvent::Kind::FirstMarked

// LiuParams of a scenario: the grid is the scenario map, the swarm its UAVs.
LiuParams params_of(const ScenarioConfig& s) {
  LiuParams p = s.config_of<LiuConfig>().params;
  p.grid_width = s.width;
  p.grid_height = s.height;
  p.uav_count = s.uavs;
  return p;
}

// Position [m] -> cell units (cell centre = integer), kept inside `cell` so
// that rounding the reported state gives back the cell the UAV is over (a UAV
// exactly on a cell border belongs to the cell floor(p / s) is, Liu 2022 Algorithm 1's
// "map(int, P)"; lround would give the other one at the low border of cell 0).
double to_cell_units(double p_m, int32_t cell, double cell_size_m) {
  constexpr double kInside = 1e-9;  // [cell]
  return std::clamp(p_m / cell_size_m - 0.5, cell - 0.5 + kInside, cell + 0.5 - kInside);
}

class LiuUavPolicy final : public UavPolicy {
 public:
  LiuUavPolicy(const ScenarioConfig& s, const MapGeometry& geo, const World& /*world*/, uint32_t id)
      : s_(&s),
        geo_(&geo),
        p_(params_of(s)),
        rng_(stream_seed(s.seed, "liu-uav", id)),
        sensor_(stream_seed(s.seed, "liu-sensor", id)) {
    const LiuConfig& c = s.config_of<LiuConfig>();
    const Cell start = start_cell(s, id);
    if (c.search == LiuPolicy::kLawnmower) {
      // Mowers start at the centre of their lane's lower-left cell (pheromesh/liu/swarm.hpp).
      mower_ = LiuMower{lawnmower_lane(id, s.uavs, s.width, s.height)};
      uav_.position = cell_centre(lawnmower_start(mower_->lane).cell, p_.cell_size_m);
    } else if (c.start_point == LiuStartPoint::kCorner) {
      uav_.position = Vec2{start.x * p_.cell_size_m, start.y * p_.cell_size_m};
    } else {
      uav_.position = cell_centre(start, p_.cell_size_m);
    }
    if (!mower_ && c.start_velocity == LiuStartVelocity::kRandomHeading) {
      const Vec2 d = random_direction(rng_);  // Liu 2022 eq. (12), Liu 2022 Sec. 2.2 "maximum velocity"
      uav_.velocity = Vec2{d.x * p_.max_speed_mps, d.y * p_.max_speed_mps};
    }
    cell_ = cell_of(uav_.position, p_);
    for (std::size_t t = 0; t < s.targets.size(); ++t) target_cells_.push_back(s.targets[t]);
  }

  void step(const UavView& view, UavActions& out) override {
    if (view.tick == 0) {
      // The start cell counts as visited but is not observed (the UAV has not
      // "arrived" there; pheromesh/liu/swarm.hpp).
      DepositMsg d;
      d.region = geo_->region_of(cell_);
      d.kind = static_cast<uint8_t>(DepositKind::LayerAdd);
      d.layer = static_cast<uint8_t>(kVisited);
      d.cell = cell_;
      d.amount = 1.0F;
      out.deposits.push_back(d);
    } else {
      decide(view);
      fly(out);
    }
    out.state.x = to_cell_units(uav_.position.x, cell_.x, p_.cell_size_m);
    out.state.y = to_cell_units(uav_.position.y, cell_.y, p_.cell_size_m);
    // [m/s] -> [cell/tick]
    const double per_tick = p_.cycle_s / p_.cell_size_m;
    out.state.vx = uav_.velocity.x * per_tick;
    out.state.vy = uav_.velocity.y * per_tick;
    heading_ = heading_of_velocity(uav_.velocity.x, uav_.velocity.y, heading_);
    out.state.heading = heading_;
    out.state.role = static_cast<uint8_t>(Role::Searcher);
  }

  [[nodiscard]] Cell cell() const override { return cell_; }

 private:
  // One velocity per cycle from the state at its start (pheromesh/liu/swarm.hpp).
  void decide(const UavView& view) {
    if (mower_) return;  // Liu 2022 eq. (14) needs no decision
    const LiuConfig& c = s_->config_of<LiuConfig>();
    others_.clear();
    // The UAVs this one sees (states of tick - 1, by id), [cell] -> [m].
    const double to_mps = p_.cell_size_m / p_.cycle_s;
    for (const UavStateMsg& n : view.neighbours) {
      others_.push_back({{(n.x + 0.5) * p_.cell_size_m, (n.y + 0.5) * p_.cell_size_m}, {n.vx * to_mps, n.vy * to_mps}});
    }
    const TileCache* tiles = view.tiles;
    const bool release = c.release_confirmed_cells;
    const TpmLookup tpm = [tiles, release](Cell cell) -> std::optional<double> {
      if (tiles == nullptr) return std::nullopt;
      if (release) {
        const auto confirmed = tiles->value(kConfirmed, cell);
        if (!confirmed || *confirmed != 0.0F) return std::nullopt;  // Liu 2022 Sec. 4: found targets release the UAVs
      }
      const auto p = tiles->value(kTpm, cell);
      if (!p) return std::nullopt;
      return static_cast<double>(*p);
    };
    LiuMove move;
    switch (c.search) {
      case LiuPolicy::kEsustpm:
        move = esustpm_step(uav_, others_, tpm, p_);
        break;  // Liu 2022 eq. (6), Liu 2022 eq. (7), Liu 2022 eq. (8), Liu 2022 eq. (9)
      case LiuPolicy::kRandom:
        move = random_search_step(uav_, rng_, p_);
        break;  // Liu 2022 eq. (12), Liu 2022 eq. (13)
      case LiuPolicy::kBoids:
        move = boids_step(uav_, others_, p_);
        break;  // Liu 2022 Sec. 5.1.4
      case LiuPolicy::kGuidedBoids:
        move = boids_guided_step(uav_, others_, tpm, p_);
        break;  // Liu 2022 Sec. 5.1.5
      case LiuPolicy::kEsustpmDisperse:
        move = esustpm_disperse_step(uav_, others_, tpm, p_);
        break;  // ours
      case LiuPolicy::kLawnmower:
        return;
    }
    uav_.velocity = move.velocity;
  }

  // The cycle in Δt steps (Liu 2022 eq. (10), Liu 2022 eq. (11)); one Observation per cell entered.
  void fly(UavActions& out) {
    const auto substeps = static_cast<uint32_t>(std::max(1.0, std::round(p_.cycle_s / p_.dt_s)));
    const double dt = p_.cycle_s / substeps;
    for (uint32_t k = 0; k < substeps; ++k) {
      if (mower_) {
        mower_advance(*mower_, uav_, dt, p_);
      } else {
        uav_ = advance_uav(uav_, uav_.velocity, dt, p_);
      }
      const Cell now = cell_of(uav_.position, p_);
      if (now == cell_) continue;
      cell_ = now;
      observe(now, out);
    }
  }

  void observe(Cell c, UavActions& out) {
    const auto it = std::find(target_cells_.begin(), target_cells_.end(), c);
    const bool target = it != target_cells_.end();
    bool detected = target;  // Liu 2022 Algorithm 1: the branch is on the truth
    if (s_->config_of<LiuConfig>().sensor == LiuSensor::kNoisy) {
      const double draw = sensor_.uniform01();  // Liu 2022 Sec. 2.1: P_d on a target cell, P_f elsewhere
      detected = target ? draw < p_.p_detection : draw < p_.p_false_alarm;
    }
    DepositMsg d;
    d.region = geo_->region_of(c);
    d.kind = static_cast<uint8_t>(DepositKind::Observation);
    d.cell = c;
    d.amount = detected ? 1.0F : 0.0F;
    out.deposits.push_back(d);
    if (target && detected) {
      out.detections.push_back({0, 0, static_cast<int32_t>(it - target_cells_.begin()), c});
    }
  }

  const ScenarioConfig* s_;
  const MapGeometry* geo_;
  LiuParams p_;
  Rng rng_;     // start heading, random search (Liu 2022 eq. (12))
  Rng sensor_;  // this UAV's sensor noise
  LiuUav uav_;  // [m], [m/s]
  Cell cell_{};
  uint8_t heading_ = 0;
  std::optional<LiuMower> mower_;
  std::vector<Cell> target_cells_;  // ground truth for the simulated sensor
  std::vector<LiuUav> others_;
};

class LiuPlace final : public PlaceModel {
 public:
  LiuPlace(const ScenarioConfig& s, const MapGeometry& geo, RegionId region)
      : region_(region), rect_(geo.region_rect(region)), tpm_(make_tpm(s, rect_)) {
    visited_.assign(static_cast<std::size_t>(rect_.area()), 0);
    confirmed_.assign(static_cast<std::size_t>(rect_.area()), 0);
  }

  std::optional<std::string> apply(const DepositMsg& d, uint32_t tick, std::vector<TargetEventMsg>& events) override {
    if (!rect_.contains(d.cell)) return "cell outside the region";
    switch (static_cast<DepositKind>(d.kind)) {
      case DepositKind::Observation: {
        if (d.amount != 0.0F && d.amount != 1.0F) return "observation amount must be 0 (miss) or 1 (detection)";
        tpm_.observe(d.cell, d.amount == 1.0F);  // Liu 2022 eq. (4) or Liu 2022 eq. (5)
        visited_[index(d.cell)] = 1;
        uint8_t& confirmed = confirmed_[index(d.cell)];
        if (confirmed == 0 && tpm_.confirmed(d.cell)) {  // Liu 2022 Sec. 2.4: P > θ
          confirmed = 1;
          events.push_back({region_, tick, kFirstMarked, d.cell, 0});
        }
        return std::nullopt;
      }
      case DepositKind::LayerAdd:
        if (d.layer != kVisited) return "the liu policy accepts LayerAdd only on layer visited";
        if (d.amount > 0.0F) visited_[index(d.cell)] = 1;  // a start cell (capped at 1)
        return std::nullopt;
      default:
        return "deposit kind " + std::to_string(d.kind) + " is not used by the liu policy";
    }
  }

  HaloRing begin_step(uint32_t /*tick*/, std::vector<TargetEventMsg>& /*events*/) override {
    return HaloRing{region_, {}, {}};  // no diffusion
  }
  void accept_halo(const Rect& /*neighbour_rect*/, const HaloRing& /*ring*/) override {}
  void finish_step() override {}  // no evaporation (Liu 2022 eq. (3))

  [[nodiscard]] float value(int layer, Cell c) const override {
    if (!rect_.contains(c)) return 0.0F;
    switch (layer) {
      case kTpm:
        return static_cast<float>(tpm_.probability(c));
      case kVisited:
        return static_cast<float>(visited_[index(c)]);
      case kConfirmed:
        return static_cast<float>(confirmed_[index(c)]);
      default:
        return 0.0F;
    }
  }

 private:
  static TargetProbabilityMap make_tpm(const ScenarioConfig& s, Rect rect) {
    const LiuParams p = params_of(s);
    // The prior of the whole map (Liu 2022 eq. (1), Liu 2022 eq. (2)), then the region's part: each
    // place agent computes the same map, so the parts fit seamlessly.
    LiuSwarmConfig cfg = liu_swarm_config_of(s.config_of<LiuConfig>(), s.targets);
    cfg.params = p;
    const std::vector<double> prior = liu_prior_map(cfg);
    auto made = TargetProbabilityMap::from_map(rect, prior, s.width, s.height, p);
    if (made) return std::move(made.value());
    return TargetProbabilityMap(rect, p);  // unreachable for a validated scenario
  }
  [[nodiscard]] std::size_t index(Cell c) const {
    return static_cast<std::size_t>(c.y - rect_.y0) * static_cast<std::size_t>(rect_.w) +
           static_cast<std::size_t>(c.x - rect_.x0);
  }

  RegionId region_;
  Rect rect_;
  TargetProbabilityMap tpm_;
  std::vector<uint8_t> visited_;
  std::vector<uint8_t> confirmed_;
};

}  // namespace

double liu_view_radius_cells(const LiuParams& p) {
  // Smallest distance beyond which |β_i(d)| < 1e-3 m/s for every rule (the
  // bound |k| t |d - c| exp(-(d - c)²/δ²) of Liu 2022 eq. (7), Liu 2022 eq. (8), Liu 2022 eq. (9) falls monotonically
  // once d - c > δ/√2).
  constexpr double kNegligible = 1e-3;  // [m/s]
  double horizon = 0.0;                 // [m]
  for (std::size_t i = 0; i < 4; ++i) {
    const double delta = std::abs(p.delta[i]);
    double e = delta / std::sqrt(2.0);
    const double scale = std::abs(p.k[i] * p.t[i]);
    while (scale * e * std::exp(-e * e / (delta * delta)) >= kNegligible && e < 1e6) e += 1.0;
    horizon = std::max(horizon, p.c[i] + e);
  }
  horizon = std::max(horizon, p.boids_safe_distance_m);
  return std::max(1.0, std::ceil(horizon / p.cell_size_m));
}

LiuSwarmConfig liu_swarm_config_of(const LiuConfig& c, const std::vector<Cell>& targets) {
  LiuSwarmConfig out;
  out.params = c.params;
  out.policy = c.search;
  out.targets.clear();
  for (const Cell& t : targets) out.targets.push_back(cell_centre(t, c.params.cell_size_m));
  out.wrong_prior_centres.clear();
  for (const Cell& w : c.wrong_prior_cells) out.wrong_prior_centres.push_back(cell_centre(w, c.params.cell_size_m));
  out.prior = c.prior;
  out.prior_sigma_cells = c.prior_sigma_cells;
  out.prior_weight = c.prior_weight;
  out.release_confirmed_cells = c.release_confirmed_cells;
  out.sensor = c.sensor;
  out.start_velocity = c.start_velocity;
  return out;
}

PolicyTraits liu_traits(const ScenarioConfig& s) {
  PolicyTraits t;
  t.layers = {"tpm", "visited", "confirmed"};
  // The sensor looks at the cell the UAV is in (one TPM update per cell
  // entered): coverage counts that cell only.
  t.sensor_radius = 0.5;
  const LiuConfig& c = s.config_of<LiuConfig>();
  t.view_radius = c.view_radius_cells ? *c.view_radius_cells : liu_view_radius_cells(c.params);
  // One cycle at the maximum speed (Liu 2022 Sec. 5), twice for margin [cell/tick].
  t.max_step = 2.0 * c.params.max_speed_mps * c.params.cycle_s / c.params.cell_size_m;
  t.layer_ranges = {{0.0F, 1.0F}, {0.0F, 1.0F}, {0.0F, 1.0F}};  // a probability (Liu 2022 eq. (3)) and two flags
  // Mowers start at their lane's lower-left cell (LiuUavPolicy), not at the
  // swarm's start cells: their gateways judge their first states from there
  // (judged from the start cells, a mower's first states were refused as
  // implausible, and with them, since issue 42 D4, the deposits they carried).
  if (c.search == LiuPolicy::kLawnmower) {
    for (uint32_t i = 0; i < s.uavs; ++i)
      t.starts.push_back(lawnmower_start(lawnmower_lane(i, s.uavs, s.width, s.height)).cell);
  }
  return t;
}

std::unique_ptr<UavPolicy> make_liu_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                        uint32_t id) {
  return std::make_unique<LiuUavPolicy>(s, geo, world, id);
}

std::unique_ptr<PlaceModel> make_liu_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region) {
  return std::make_unique<LiuPlace>(s, geo, region);
}

std::map<std::string, double> liu_field_summary(const ScenarioConfig& s, const FieldLookup& value) {
  std::vector<double> tpm;
  tpm.reserve(static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height));
  double visited = 0.0;
  double confirmed = 0.0;
  double real = 0.0;
  for (int32_t y = 0; y < s.height; ++y) {
    for (int32_t x = 0; x < s.width; ++x) {
      const Cell c{x, y};
      tpm.push_back(static_cast<double>(value(kTpm, c)));
      if (value(kVisited, c) != 0.0F) visited += 1.0;
      if (value(kConfirmed, c) != 0.0F) {
        confirmed += 1.0;
        if (std::find(s.targets.begin(), s.targets.end(), c) != s.targets.end()) real += 1.0;
      }
    }
  }
  return {
      {"visited_cells", visited},                                     // Liu 2022 Table 2 "visited grid number"
      {"environmental_uncertainty", environmental_uncertainty(tpm)},  // [bit] Liu 2022 Table 2, -Σ P log2 P
      {"confirmed_cells", confirmed},                                 // cells with P > θ once
      {"real_targets_confirmed", real},                               // Liu 2022 Table 2 "target found number"
      {"false_confirmations", confirmed - real},
  };
}

}  // namespace pheromesh::core
