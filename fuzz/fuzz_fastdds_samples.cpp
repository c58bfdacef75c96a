// Fuzz harness: a sample as it arrives from the network at a Fast DDS reader
// of pheromesh — serialized bytes (CDR encapsulation + body) -> fastddsgen's
// deserialize into the generated type (what the DataReader runs before take)
// -> the bus's conversion and structure checks (Convert<M>::in in
// common/bus/src/fastdds_samples.hpp, the code the Fast DDS transport's take
// runs) -> the core's semantic checks, against the small-test map (30 x 30,
// 2 x 2 regions).
// The first input byte picks the topic type, the rest is the payload.
//
// With PHEROMESH_FUZZ_WRITE_SEEDS=DIR, the harness first writes one
// well-formed sample of each type to DIR (how fuzz/corpus/
// fuzz_fastdds_samples/seed-* were made).
//
// Cyclone's receive path is not covered: its deserialisation needs a
// sertype, which the C API makes only with a participant and a topic
// (docs/fuzzing.md).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include <fastdds/rtps/common/SerializedPayload.h>

#include "fastdds_samples.hpp"
#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/messages.hpp"
#include "pheromesh/core/scenario.hpp"

using namespace pheromesh;
namespace in = bus::fastdds_samples;
namespace msg = pheromesh::msg;

namespace {

const core::MapGeometry kGeo{30, 30, 6, 2, 2};  // scenarios/small-test.textproto
constexpr int kLayers = 3;                      // the Shao search's

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

template <typename PubSub, typename T>
void write_seed(const std::string& dir, const char* name, uint8_t selector, T sample) {
  PubSub type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&sample)());
  if (!type.serialize(&sample, &payload)) std::abort();
  std::ofstream out(dir + "/seed-" + name, std::ios::binary);
  out.put(static_cast<char>(selector));
  out.write(reinterpret_cast<const char*>(payload.data), payload.length);
}

msg::TilePatch patch() {
  msg::TilePatch t;
  t.layer(1);
  t.tx(1);
  t.ty(0);
  t.width(6);
  t.height(6);
  t.values(std::vector<float>(36, 0.25F));
  return t;
}

msg::UavState state() {
  msg::UavState u;
  u.uav(2);
  u.tick(5);
  u.x(4.0);
  u.y(7.5);
  u.vx(1.0);
  u.heading(3);
  u.view_x(4);
  u.view_y(7);
  return u;
}

void write_seeds(const std::string& dir) {
  msg::Deposit d;
  d.uav(1);
  d.seq(4);
  d.region(0);
  d.kind(1);
  d.x(3);
  d.y(3);
  d.amount(1.0F);
  msg::Deposit visit = d;
  visit.seq(5);
  visit.kind(0);
  msg::DepositBatch batch;
  batch.forwarder(2);
  batch.tick(6);
  batch.deposits({d, visit});
  write_seed<msg::DepositBatchPubSubType>(dir, "deposit", 0, batch);
  msg::TileState t;
  t.layer(0);
  t.tx(2);
  t.ty(1);
  t.region(1);
  t.width(6);
  t.height(6);
  t.values(std::vector<float>(36, 0.5F));
  write_seed<msg::TileStatePubSubType>(dir, "tile", 1, t);
  write_seed<msg::UavStatePubSubType>(dir, "uav-state", 2, state());
  msg::RegionField f;
  f.region(1);
  f.chunks(1);
  f.tiles({patch()});
  f.uavs({state()});
  write_seed<msg::RegionFieldPubSubType>(dir, "field", 3, f);
  msg::View v;
  v.uav(2);
  v.tiles({patch(), patch()});
  msg::Neighbour near;
  near.uav(1);
  near.tick(1);
  near.x(3.5);
  near.y(4.5);
  near.view_x(3);
  near.view_y(4);
  v.uavs({near});
  write_seed<msg::ViewPubSubType>(dir, "view", 4, v);
  msg::ClockCommand vc;  // a lockstep view's UAV clock
  vc.tick(1);
  msg::TileCount occupied;
  occupied.tx(1);
  occupied.count(1);
  vc.occupancy({occupied});
  v.clock({vc});
  write_seed<msg::ViewPubSubType>(dir, "view-clock", 4, v);
  msg::Halo h;
  h.region(0);
  h.target(std::vector<float>(core::ring_size(kGeo.region_rect(0)), 0.1F));
  h.obstacle(std::vector<float>(core::ring_size(kGeo.region_rect(0)), 0.0F));
  write_seed<msg::HaloPubSubType>(dir, "halo", 5, h);
  msg::Broadcast b;
  b.uav(1);
  b.kind(0);
  b.values({1.0, 2.0, 0.5, 0.5, 0.0});
  write_seed<msg::BroadcastPubSubType>(dir, "broadcast", 6, b);
  msg::ClockCommand c;
  c.tick(3);
  c.phase(1);
  msg::TileCount tc;
  tc.tx(1);
  tc.count(2);
  c.occupancy({tc});
  msg::RegionCount rc;
  rc.region(1);
  rc.count(5);
  c.deposits({rc});
  c.absent({2});
  msg::ServedUav su;
  su.uav(4);
  su.region(1);
  su.x(3.5);
  su.view_x(3);
  c.served({su});
  write_seed<msg::ClockCommandPubSubType>(dir, "clock", 7, c);
  msg::PhaseDone pd;
  pd.process(core::process_key(core::kRoleUav, 2));
  pd.deposits({rc});
  write_seed<msg::PhaseDonePubSubType>(dir, "phase-done", 8, pd);
  msg::RunScenario rs;
  const std::string text = "map { width: 30 height: 30 tile_size: 6 regions_x: 2 regions_y: 2 }\nswarm { uavs: 4 }\n";
  rs.text(std::vector<uint8_t>(text.begin(), text.end()));
  rs.uavs(4);
  write_seed<msg::RunScenarioPubSubType>(dir, "run-scenario", 9, rs);
  msg::Command k;
  k.kind(3);
  k.x(2);
  k.y(2);
  k.w(3);
  k.h(1);
  write_seed<msg::CommandPubSubType>(dir, "command", 10, k);
  msg::Detection det;
  det.uav(1);
  det.target(0);
  det.x(22);
  det.y(8);
  write_seed<msg::DetectionPubSubType>(dir, "detection", 11, det);
  msg::TargetEvent te;
  te.kind(1);
  te.x(22);
  te.y(8);
  write_seed<msg::TargetEventPubSubType>(dir, "target-event", 12, te);
  msg::PlaceHealth ph;
  ph.region(1);
  ph.deposits_received(9);
  write_seed<msg::PlaceHealthPubSubType>(dir, "health", 13, ph);
  write_seed<msg::TilePatchPubSubType>(dir, "tile-patch", 14, patch());
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  if (const char* dir = std::getenv("PHEROMESH_FUZZ_WRITE_SEEDS"); dir != nullptr) write_seeds(dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const uint8_t* p = data + 1;
  const std::size_t n = size - 1;
  switch (data[0] % 15) {
    case 0: {
      msg::DepositBatch s;
      if (!deserialize<msg::DepositBatchPubSubType>(p, n, s)) return 0;
      if (auto b = in::Convert<core::DepositBatchMsg>::in(s)) {
        for (const auto& d : b->deposits) {
          (void)core::check_deposit(d, kGeo, d.region < kGeo.region_count() ? d.region : 0, kLayers);
        }
      }
      break;
    }
    case 1: {
      msg::TileState s;
      if (!deserialize<msg::TileStatePubSubType>(p, n, s)) return 0;
      if (auto t = in::Convert<core::TileMsg>::in(s)) (void)core::check_tile(*t, kGeo, kLayers);
      break;
    }
    case 2: {
      msg::UavState s;
      if (!deserialize<msg::UavStatePubSubType>(p, n, s)) return 0;
      if (auto u = in::Convert<core::UavStateMsg>::in(s)) (void)core::check_uav_state(*u, kGeo);
      break;
    }
    case 3: {
      msg::RegionField s;
      if (!deserialize<msg::RegionFieldPubSubType>(p, n, s)) return 0;
      if (auto f = in::Convert<core::FieldMsg>::in(s)) check_nested(f->tiles, f->uavs);
      break;
    }
    case 4: {
      msg::View s;
      if (!deserialize<msg::ViewPubSubType>(p, n, s)) return 0;
      if (auto v = in::Convert<core::ViewMsg>::in(s)) {
        check_nested(v->tiles, v->uavs);
        if (v->clock && v->clock->occupancy.size() > core::kMaxOccupancy) std::abort();
      }
      break;
    }
    case 5: {
      msg::Halo s;
      if (!deserialize<msg::HaloPubSubType>(p, n, s)) return 0;
      if (auto h = in::Convert<core::HaloMsg>::in(s)) (void)core::check_halo(*h, kGeo);
      break;
    }
    case 6: {
      msg::Broadcast s;
      if (!deserialize<msg::BroadcastPubSubType>(p, n, s)) return 0;
      if (auto b = in::Convert<core::BroadcastMsg>::in(s)) (void)core::check_broadcast(*b);
      break;
    }
    case 7: {
      msg::ClockCommand s;
      if (!deserialize<msg::ClockCommandPubSubType>(p, n, s)) return 0;
      (void)in::Convert<core::ClockMsg>::in(s);
      break;
    }
    case 8: {
      msg::PhaseDone s;
      if (!deserialize<msg::PhaseDonePubSubType>(p, n, s)) return 0;
      (void)in::Convert<core::PhaseDoneMsg>::in(s);
      break;
    }
    case 9: {
      msg::RunScenario s;
      if (!deserialize<msg::RunScenarioPubSubType>(p, n, s)) return 0;
      // A monitor (pheromesh attach) runs the scenario it receives.
      if (auto m = in::Convert<core::ScenarioMsg>::in(s)) (void)core::parse_scenario(m->text, "RunScenario");
      break;
    }
    case 10: {
      msg::Command s;
      if (!deserialize<msg::CommandPubSubType>(p, n, s)) return 0;
      (void)in::Convert<core::CommandMsg>::in(s);
      break;
    }
    case 11: {
      msg::Detection s;
      if (!deserialize<msg::DetectionPubSubType>(p, n, s)) return 0;
      (void)in::Convert<core::DetectionMsg>::in(s);
      break;
    }
    case 12: {
      msg::TargetEvent s;
      if (!deserialize<msg::TargetEventPubSubType>(p, n, s)) return 0;
      if (auto e = in::Convert<core::TargetEventMsg>::in(s))
        (void)core::to_string(static_cast<core::TargetEventKind>(e->kind));
      break;
    }
    case 13: {
      msg::PlaceHealth s;
      if (!deserialize<msg::PlaceHealthPubSubType>(p, n, s)) return 0;
      (void)in::Convert<core::HealthMsg>::in(s);
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
