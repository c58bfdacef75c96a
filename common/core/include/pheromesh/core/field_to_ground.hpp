// What a place agent sends the ground station of its field, and when. The
// ground station shows the field (console, `attach`) and writes the last one
// (final_field.txt); it does not need every tick of every tile:
//  * lockstep: every tile, every tick (the conductor holds the last tick's
//    fields before its Stop, and the final field must be exact);
//  * realtime: every `every` ticks (the console's rate), the tiles that
//    changed since they were last sent to the ground, every tile on every
//    `full_every`-th send (a monitor attached late, a sample lost) and on
//    the last tick.
// A region's ground traffic then follows what changes in it at the console
// rate instead of its area at the tick rate.
#pragma once

#include <cstdint>
#include <map>
#include <tuple>
#include <vector>

#include "pheromesh/core/messages.hpp"

namespace pheromesh::core {

class FieldToGround {
 public:
  // Every tile every tick.
  FieldToGround() = default;
  // every >= 1 ticks; every full_every >= 1 sends a full one.
  FieldToGround(uint32_t every, uint32_t full_every);
  // Realtime at `tick_rate_hz` for a console at `field_hz`: every
  // max(1, round(tick_rate_hz / field_hz)) ticks, a full field every 2 s.
  static FieldToGround at_rate(double tick_rate_hz, double field_hz);

  // Whether the field of `tick` goes out (`last`: the process's last tick).
  [[nodiscard]] bool due(uint32_t tick, bool last) const;
  // Of `all` (every tile of the region at one tick), those to send: appended
  // to `out`. Call once per tick that is due.
  void select(const std::vector<TileMsg>& all, bool last, std::vector<TileMsg>& out);

  [[nodiscard]] uint32_t every() const { return every_; }

 private:
  uint32_t every_ = 1;
  uint32_t full_every_ = 1;
  uint32_t sends_ = 0;
  std::map<std::tuple<int32_t, int32_t, uint8_t>, std::vector<float>> sent_;  // (tx, ty, layer) -> values last sent
};

}  // namespace pheromesh::core
