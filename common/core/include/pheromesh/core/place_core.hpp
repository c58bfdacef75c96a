// One place agent's logic without any transport: deposit checking and
// accounting in canonical order, the scenario policy's layers of its region
// (PlaceModel, policy.hpp), the halo exchange and the tiles it publishes. The pheromesh-place
// process and the in-process simulator both drive this class.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/plausibility.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"

namespace pheromesh::core {

// Accounting of deposits, with the reason of every rejection.
struct DepositLedger {
  uint64_t received = 0;
  uint64_t applied = 0;
  std::map<std::string, uint64_t> rejected_by_reason;
  // Samples refused as implausible (plausibility.hpp): of the rejected
  // deposits those of forged UAV ids and sequence numbers far ahead; halo rings
  // out of range.
  RefusalCounts refused;
  [[nodiscard]] uint64_t rejected() const;
};

class PlaceCore {
 public:
  PlaceCore(const ScenarioConfig& scenario, RegionId region);
  // The field keeps a pointer to geo_: pinned in memory.
  PlaceCore(const PlaceCore&) = delete;
  PlaceCore& operator=(const PlaceCore&) = delete;

  // Phase 1 of a tick: applies `deposits` in the canonical order (UAV id, then
  // sequence number; the vector is sorted in place), advances the revisit
  // timers to `tick`, computes the diffusion sources. Returns this region's
  // halo ring for the neighbours; `events` receives target events and
  // `rejections` (if given) one line per rejected deposit.
  // `reach` (if given) says why a deposit lands where its UAV cannot have put
  // it (check_deposit_reach with the UAV's last accepted state as this place
  // knows it); such a deposit is rejected and refused (ImplausibleDeposit),
  // and its sequence number is not latched.
  using DepositReach = std::function<std::optional<std::string>(const DepositMsg&)>;
  HaloRing begin_tick(std::vector<DepositMsg>& deposits, uint32_t tick, std::vector<TargetEventMsg>& events,
                      std::vector<std::string>* rejections = nullptr, const DepositReach* reach = nullptr);
  // Whether begin_tick at `tick` would refuse `d` as implausible (a UAV id
  // outside the swarm, a sequence number far ahead): lockstep place agents
  // count only the others toward the deposits a tick announced.
  [[nodiscard]] bool refuses(const DepositMsg& d, uint32_t tick) const;
  // begin_tick at `tick` would turn `d` away for what it says, whoever
  // sent it: malformed for this region (check_deposit), or refuses(d, tick).
  [[nodiscard]] bool refuses_outright(const DepositMsg& d, uint32_t tick) const;
  // Deposits that can no longer be applied (they arrived after the last
  // lockstep tick): counted as rejected with `reason`.
  void reject(const std::vector<DepositMsg>& deposits, const std::string& reason);
  // A neighbour's ring (checked; false if malformed or out of its layers'
  // range - counted in ledger().refused - and ignored).
  bool accept_halo(const HaloMsg& h);
  // Phase 2: the policy's layer update (e.g. Shao 2020 eq. (1), Shao 2020 eq. (2), Shao 2020 eq. (3), Shao 2020 eq. (4), Shao 2020 eq. (5), Shao 2020 eq. (6), Shao 2020 eq. (7), Shao 2020 eq. (8)).
  void finish_tick();

  // Tiles of this region at `tick`: every tile and layer, or only those that
  // changed since the last call with Changed.
  enum class TileSelection : uint8_t { All, Changed };
  void tiles(uint32_t tick, TileSelection which, std::vector<TileMsg>& out);
  // One tile's messages, every layer in order, as tiles(tick, All) gives them
  // (the simulator builds only the tiles some UAV reads); false and nothing
  // appended for a tile this region does not own. Leaves what Changed
  // compares against untouched.
  bool tile(TileCoord t, uint32_t tick, std::vector<TileMsg>& out) const;

  [[nodiscard]] const DepositLedger& ledger() const { return ledger_; }
  [[nodiscard]] float value(int layer, Cell c) const { return model_->value(layer, c); }  // c in the region
  [[nodiscard]] int layer_count() const { return layers_; }
  [[nodiscard]] RegionId region() const { return region_; }
  [[nodiscard]] const std::vector<RegionId>& neighbours() const { return neighbours_; }
  [[nodiscard]] const std::vector<TileCoord>& owned_tiles() const { return tiles_; }

 private:
  // The sequence rule, judged here only (begin_tick, refuses): `d`'s
  // sequence number is beyond what its UAV can have reached by `tick` since
  // its last applied deposit (check_seq_reachable). A repeated one is
  // DepositDesk's (a copy) or begin_tick's (a duplicate) to drop.
  [[nodiscard]] bool seq_far_ahead(const DepositMsg& d, uint32_t tick) const;
  MapGeometry geo_;
  RegionId region_;
  int layers_;
  std::unique_ptr<PlaceModel> model_;
  std::vector<TileCoord> tiles_;
  std::vector<RegionId> neighbours_;
  uint32_t swarm_;  // UAV ids are 0..swarm_-1
  ValueRange ring_range_;  // what a halo ring value can be (the widest range of the layers)
  struct SeqMark {
    uint32_t seq = 0;
    uint32_t tick = 0;  // receiver tick it was accepted at
  };
  std::map<uint32_t, SeqMark> last_seq_;  // per UAV: highest applied deposit seq
  std::map<std::pair<std::size_t, int>, std::vector<float>> published_;  // (tile, layer) -> values last sent
  DepositLedger ledger_;
  [[nodiscard]] TileMsg tile_layer(TileCoord t, int layer, uint32_t tick) const;
};

// A region's border ring as one neighbour receives it (local traffic): only
// the cells that neighbour's diffusion reads (ring_indices_facing). Empty
// rings (policies without diffusion) stay empty.
HaloMsg trim_halo(const HaloMsg& full, const MapGeometry& geo, RegionId receiver);
// The receiver's side: the full ring again, with 0 where it reads nothing;
// nullopt if the sender is unknown or the part's sizes are not what the
// geometry gives (a malformed or forged halo).
std::optional<HaloMsg> expand_halo(const HaloMsg& part, const MapGeometry& geo, RegionId receiver);

}  // namespace pheromesh::core
