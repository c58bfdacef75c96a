// Fuzz harness: a sample as it arrives from the network at a Fast DDS reader
// of pheromesh — serialized bytes (CDR encapsulation + body) -> fastddsgen's
// deserialize into the generated type (what the DataReader runs before take)
// -> the bus's conversion and structure checks (common/bus/src/
// fastdds_samples.hpp, the code FastDdsBus::take_* runs) -> the core's
// semantic checks, against the small-test map (30 x 30, 2 x 2 regions).
// The first input byte picks the topic type, the rest is the payload.
//
// Cyclone's receive path is not covered: its deserialisation needs a
// sertype, which the C API makes only with a participant and a topic
// (docs/fuzzing.md).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include <fastdds/rtps/common/SerializedPayload.h>

#include "fastdds_samples.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/scenario.hpp"

using namespace pheromesh;
namespace in = bus::fastdds_samples;
namespace msg = pheromesh::msg;

namespace {

const core::MapGeometry kGeo{30, 30, 6, 2, 2};  // scenarios/small-test.textproto
constexpr int kLayers = 3;                       // the Shao search's

template <typename PubSub, typename T>
bool deserialize(const uint8_t* data, std::size_t size, T& out) {
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<uint32_t>(size));
  if (size > 0) std::memcpy(payload.data, data, size);
  payload.length = static_cast<uint32_t>(size);
  in::SafePubSub<PubSub> type;  // what the bus registers
  return type.deserialize(&payload, &out);
}

void check_nested(const std::vector<core::TileMsg>& tiles, const std::vector<core::UavStateMsg>& uavs) {
  for (const auto& t : tiles) (void)core::check_tile(t, kGeo, kLayers);
  for (const auto& u : uavs) (void)core::check_uav_state(u, kGeo);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const uint8_t* p = data + 1;
  const std::size_t n = size - 1;
  switch (data[0] % 15) {
    case 0: {
      msg::Deposit s;
      if (!deserialize<msg::DepositPubSubType>(p, n, s)) return 0;
      const core::DepositMsg d = in::deposit_in(s);
      (void)core::check_deposit(d, kGeo, d.region < kGeo.region_count() ? d.region : 0, kLayers);
      break;
    }
    case 1: {
      msg::TileState s;
      if (!deserialize<msg::TileStatePubSubType>(p, n, s)) return 0;
      if (auto t = in::tile_in(s)) (void)core::check_tile(*t, kGeo, kLayers);
      break;
    }
    case 2: {
      msg::UavState s;
      if (!deserialize<msg::UavStatePubSubType>(p, n, s)) return 0;
      (void)core::check_uav_state(in::state_in(s), kGeo);
      break;
    }
    case 3: {
      msg::RegionField s;
      if (!deserialize<msg::RegionFieldPubSubType>(p, n, s)) return 0;
      if (auto f = in::field_in(s)) check_nested(f->tiles, f->uavs);
      break;
    }
    case 4: {
      msg::View s;
      if (!deserialize<msg::ViewPubSubType>(p, n, s)) return 0;
      if (auto v = in::view_in(s)) check_nested(v->tiles, v->uavs);
      break;
    }
    case 5: {
      msg::Halo s;
      if (!deserialize<msg::HaloPubSubType>(p, n, s)) return 0;
      if (auto h = in::halo_in(s)) (void)core::check_halo(*h, kGeo);
      break;
    }
    case 6: {
      msg::Broadcast s;
      if (!deserialize<msg::BroadcastPubSubType>(p, n, s)) return 0;
      if (auto b = in::broadcast_in(s)) (void)core::check_broadcast(*b);
      break;
    }
    case 7: {
      msg::ClockCommand s;
      if (!deserialize<msg::ClockCommandPubSubType>(p, n, s)) return 0;
      (void)in::clock_in(s);
      break;
    }
    case 8: {
      msg::PhaseDone s;
      if (!deserialize<msg::PhaseDonePubSubType>(p, n, s)) return 0;
      (void)in::phase_done_in(s);
      break;
    }
    case 9: {
      msg::RunScenario s;
      if (!deserialize<msg::RunScenarioPubSubType>(p, n, s)) return 0;
      // A monitor (pheromesh attach) runs the scenario it receives.
      if (auto m = in::scenario_in(s)) (void)core::parse_scenario(m->text, "RunScenario");
      break;
    }
    case 10: {
      msg::Command s;
      if (!deserialize<msg::CommandPubSubType>(p, n, s)) return 0;
      (void)in::command_in(s);
      break;
    }
    case 11: {
      msg::Detection s;
      if (!deserialize<msg::DetectionPubSubType>(p, n, s)) return 0;
      (void)in::detection_in(s);
      break;
    }
    case 12: {
      msg::TargetEvent s;
      if (!deserialize<msg::TargetEventPubSubType>(p, n, s)) return 0;
      (void)core::to_string(static_cast<core::TargetEventKind>(in::target_event_in(s).kind));
      break;
    }
    case 13: {
      msg::PlaceHealth s;
      if (!deserialize<msg::PlaceHealthPubSubType>(p, n, s)) return 0;
      (void)in::health_in(s);
      break;
    }
    default: {
      msg::TilePatch s;  // nested in View and RegionField
      (void)deserialize<msg::TilePatchPubSubType>(p, n, s);
      break;
    }
  }
  return 0;
}
