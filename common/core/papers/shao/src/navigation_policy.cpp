// The Shao 2020 navigation policy (Shao 2020 Sec. 5, Shao 2020 Algorithm 2 and Shao 2020 Algorithm 3): UAV 0 leads on
// vector (or scalar) pheromones read from its tiles (Shao 2020 eq. (12), Shao 2020 eq. (13), Shao 2020 eq. (14), Shao 2020 eq. (15)) and tells
// the swarm where it is through a LeaderState broadcast; the others flock
// after it with the modified Olfati-Saber rule (Shao 2020 eq. (17), Shao 2020 eq. (18), Shao 2020 eq. (19), Shao 2020 eq. (20), Shao 2020 eq. (21), Shao 2020 eq. (22), Shao 2020 eq. (23), Shao 2020 eq. (24)) using the states
// of the followers over their neighbourhood tiles. When the leader reaches
// the centre of the target region every UAV switches to the Shao 2020 Sec. 4 search
// (Shao 2020 Algorithm 3 lines 1-2). The place agents run the Shao layers with the
// targets and obstacles emitting from the start (make_shao_place, beacons):
// the "artificial pheromone potential field" of Shao 2020 Sec. 5. Navigating UAVs deposit
// nothing (Shao 2020 Algorithm 2 and Shao 2020 Algorithm 3 have no deposit step); searchers deposit as in Shao 2020 Sec. 4.
#include <algorithm>
#include <cmath>

#include "pheromesh/core/policy.hpp"
#include "pheromesh/shao/aco.hpp"
#include "pheromesh/shao/navigation.hpp"
#include "pheromesh/shao/policy.hpp"

namespace pheromesh::core {

namespace {

constexpr uint32_t kLeader = 0;

Cell nearest_cell(const Eigen::Vector2d& q, const MapGeometry& geo) {
  const auto x = static_cast<int32_t>(std::lround(q.x()));
  const auto y = static_cast<int32_t>(std::lround(q.y()));
  return {std::clamp(x, 0, geo.width() - 1), std::clamp(y, 0, geo.height() - 1)};
}

class ShaoNavigationUav final : public UavPolicy {
 public:
  ShaoNavigationUav(const ScenarioConfig& s, const MapGeometry& geo, const World& world, uint32_t id)
      : s_(&s), geo_(&geo), world_(&world), id_(id) {
    const Cell c = start_cell(s, id);
    q_ = {c.x, c.y};
  }

  void step(const UavView& view, UavActions& out) override {
    if (search_) {
      search_->step(view, out);
      return;
    }
    const auto& cfg = s_->config_of<ShaoNavigationConfig>();
    bool arrived = false;
    const bool holding = view.tick <= cfg.hold_ticks;
    if (id_ == kLeader) {
      if (!holding) {
        const PheromoneLookup lookup = [&view](Cell c) -> std::optional<std::array<float, 3>> {
          auto t = view.tiles->value(static_cast<int>(Layer::Target), c);
          auto o = view.tiles->value(static_cast<int>(Layer::Obstacle), c);
          auto p = view.tiles->value(static_cast<int>(Layer::Path), c);
          if (!t || !o || !p) return std::nullopt;
          return std::array<float, 3>{*t, *o, *p};
        };
        const Eigen::Vector2d centre{cfg.region_centre.x, cfg.region_centre.y};
        // Shao 2020 Algorithm 2: towards the centre once it is within
        // sensorLD, else one pheromone step (Shao 2020 eq. (12), Shao 2020 eq. (13), Shao 2020 eq. (14), Shao 2020 eq. (15)).
        const LeaderStep st = leader_algorithm2_step(q_, centre, lookup, cfg.params, cfg.leader);
        v_ = st.v;
        q_ = clamp_to_map(st.q);
        arrived = st.at_centre;
      }
      BroadcastMsg b;
      b.kind = static_cast<uint8_t>(BroadcastKind::LeaderState);
      b.values = {q_.x(), q_.y(), v_.x(), v_.y(), arrived ? 1.0 : 0.0};
      out.broadcast = std::move(b);
    } else if (!holding) {
      std::optional<FollowerState> leader;
      for (const BroadcastMsg& b : view.broadcasts) {
        if (b.uav != kLeader || b.kind != static_cast<uint8_t>(BroadcastKind::LeaderState) || b.values.size() < 5) continue;
        leader = FollowerState{{b.values[0], b.values[1]}, {b.values[2], b.values[3]}};
        arrived = b.values[4] != 0.0;
      }
      if (!arrived && leader) {
        others_.clear();
        for (const UavStateMsg& n : view.neighbours) {
          if (n.uav == kLeader || n.role != static_cast<uint8_t>(Role::Follower)) continue;
          others_.push_back({{n.x, n.y}, {n.vx, n.vy}});
        }
        // Shao 2020 eq. (17), Shao 2020 eq. (18), Shao 2020 eq. (19), Shao 2020 eq. (20), Shao 2020 eq. (21), Shao 2020 eq. (22), Shao 2020 eq. (23), Shao 2020 eq. (24).
        const FollowerStep st = follower_step({q_, v_}, others_, *leader, cfg.params);
        v_ = st.v;
        q_ = clamp_to_map(st.q);
      }
    }
    // Shao 2020 Algorithm 2 and Shao 2020 Algorithm 3 have no deposit step (Shao 2020 Algorithm 1's lines 3-9 are
    // the search's): navigating UAVs only read the potential field.
    const Cell c = nearest_cell(q_, *geo_);
    out.state.x = q_.x();
    out.state.y = q_.y();
    out.state.vx = v_.x();
    out.state.vy = v_.y();
    heading_ = heading_of_velocity(v_.x(), v_.y(), heading_);
    out.state.heading = heading_;
    out.state.role = static_cast<uint8_t>(id_ == kLeader ? Role::Leader : Role::Follower);
    if (arrived) {
      // Shao 2020 Algorithm 2 lines 3-4 / Shao 2020 Algorithm 3 lines 1-2: the search takes over
      // from the next tick, from this cell and heading.
      search_ = make_shao_search_uav_at(*s_, *geo_, *world_, id_, c, heading_);
      out.state.x = c.x;
      out.state.y = c.y;
      out.state.role = static_cast<uint8_t>(Role::Searcher);
    }
  }

  [[nodiscard]] Cell cell() const override { return search_ ? search_->cell() : nearest_cell(q_, *geo_); }

 private:
  [[nodiscard]] Eigen::Vector2d clamp_to_map(const Eigen::Vector2d& q) const {
    return {std::clamp(q.x(), 0.0, static_cast<double>(geo_->width() - 1)),
            std::clamp(q.y(), 0.0, static_cast<double>(geo_->height() - 1))};
  }

  const ScenarioConfig* s_;
  const MapGeometry* geo_;
  const World* world_;
  uint32_t id_;
  Eigen::Vector2d q_ = Eigen::Vector2d::Zero();  // [cell]
  Eigen::Vector2d v_ = Eigen::Vector2d::Zero();  // [cell/tick]
  uint8_t heading_ = 0;
  std::vector<FollowerState> others_;
  std::unique_ptr<UavPolicy> search_;  // after the leader's arrival
};

}  // namespace

PolicyTraits shao_navigation_traits(const ScenarioConfig& s) {
  PolicyTraits t = shao_search_traits(s);
  t.reads_neighbours = true;  // a follower steers by the UAVs around it (step: view.neighbours)
  const auto& p = s.config_of<ShaoNavigationConfig>().params;
  t.view_radius = std::max({t.view_radius, std::ceil(p.leader_sensor_radius) + 1.0, std::ceil(p.follower_range) + 1.0});
  // Followers' speed is not bounded (navigation.cpp: Shao 2020 gives no limit;
  // honest followers jump 30 cells and more in a tick at the border): any
  // position on the map is a plausible next one.
  t.max_step = std::hypot(static_cast<double>(s.width), static_cast<double>(s.height));
  return t;
}

std::unique_ptr<UavPolicy> make_shao_navigation_uav(const ScenarioConfig& s, const MapGeometry& geo, const World& world,
                                                    uint32_t id) {
  return std::make_unique<ShaoNavigationUav>(s, geo, world, id);
}

std::unique_ptr<PlaceModel> make_shao_navigation_place(const ScenarioConfig& s, const MapGeometry& geo, RegionId region) {
  return make_shao_place(s, geo, region, true);
}

std::map<std::string, double> shao_navigation_field_summary(const ScenarioConfig& /*s*/, const FieldLookup& /*value*/) {
  return {};
}

}  // namespace pheromesh::core
