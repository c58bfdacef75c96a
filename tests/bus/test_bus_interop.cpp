// Every pheromesh message crosses between the vendors intact, in both
// directions and within one vendor: a writer bus of vendor A and a reader bus
// of vendor B in this process, on loopback, domain 60 (66 for the realtime
// views). No integration test uses either.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/resend.hpp"

using namespace pheromesh;  // NOLINT
using Clock = std::chrono::steady_clock;

namespace {

struct Pair {
  std::string writer, reader;
};

std::string pair_name(const testing::TestParamInfo<Pair>& p) { return p.param.writer + "_to_" + p.param.reader; }
// How gtest and ctest show a pairing.
void PrintTo(const Pair& p, std::ostream* os) { *os << p.writer << " -> " << p.reader; }

std::unique_ptr<bus::Bus> make(const std::string& vendor, const std::string& name) {
  bus::BusOptions o;
  o.process_name = name;
  o.domain = 60;
  auto b = bus::make_bus(vendor, o);
  EXPECT_TRUE(static_cast<bool>(b)) << (b ? "" : b.error().message);
  return b ? std::move(b).value() : nullptr;
}

// Polls `take` until it yields something or 15 s pass (discovery included).
template <typename T>
std::vector<T> wait_for(const std::function<void(std::vector<T>&)>& take, std::size_t want = 1) {
  std::vector<T> got;
  const auto deadline = Clock::now() + std::chrono::seconds(15);
  while (got.size() < want && Clock::now() < deadline) {
    take(got);
    if (got.size() < want) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return got;
}

class Interop : public testing::TestWithParam<Pair> {
 protected:
  void SetUp() override {
    w_ = make(GetParam().writer, "writer");
    r_ = make(GetParam().reader, "reader");
    ASSERT_TRUE(w_ && r_);
  }
  std::unique_ptr<bus::Bus> w_, r_;
};

TEST_P(Interop, AViewCarriesItsUavClockToALockstepUavAsAClockOfTheProcessThatRelaysItsClocks) {
  r_->join_uav(5, 3);
  r_->join_clock_tree(std::vector<core::RegionId>{3, 4});
  w_->subscribe_uav_reports(3);  // place agent 3: its relay writers
  core::ClockMsg uav_clock;
  uav_clock.tick = 19;
  uav_clock.phase = static_cast<uint8_t>(core::ClockPhase::Uav);
  uav_clock.broadcasts = 2;
  uav_clock.occupancy = {{{1, 2}, 3}, {{4, 5}, 6}};
  uav_clock.absent = {2, 9};
  core::ViewMsg view{5, 18, {core::TileMsg{0, {1, 2}, 0, 0, 1, 1, {4.0F}}}, {}};
  view.clock = uav_clock;
  ASSERT_TRUE(w_->publish_view(view));
  const auto clocks = wait_for<core::ClockMsg>([&](auto& v) { r_->take_clock(v); });
  ASSERT_EQ(clocks.size(), 1U);
  EXPECT_EQ(clocks[0].tick, 19U);
  EXPECT_EQ(clocks[0].phase, static_cast<uint8_t>(core::ClockPhase::Uav));
  EXPECT_EQ(clocks[0].broadcasts, 2U);
  ASSERT_EQ(clocks[0].occupancy.size(), 2U);
  EXPECT_EQ(clocks[0].occupancy[1].tile.tx, 4);
  EXPECT_EQ(clocks[0].occupancy[1].count, 6U);
  EXPECT_EQ(clocks[0].absent, (std::vector<core::RegionId>{2, 9}));
  EXPECT_FALSE(clocks[0].next_uav_phase);
  EXPECT_NE(clocks[0].writer, 0U);
  std::vector<core::ViewMsg> views;
  r_->take_views(views);
  ASSERT_EQ(views.size(), 1U) << "take_clock holds the view for take_views";
  EXPECT_EQ(views[0].tick, 18U);
  ASSERT_EQ(views[0].tiles.size(), 1U);
  EXPECT_FALSE(views[0].clock.has_value());
  // The clock the same process relays names the same writer.
  core::ClockMsg next = uav_clock;
  next.tick = 20;
  ASSERT_TRUE(w_->relay_clock(next, 3));
  const auto relayed = wait_for<core::ClockMsg>([&](auto& v) { r_->take_clock(v); });
  ASSERT_EQ(relayed.size(), 1U);
  EXPECT_EQ(relayed[0].tick, 20U);
  EXPECT_EQ(relayed[0].writer, clocks[0].writer);
  EXPECT_EQ(r_->stats().samples_dropped, 0U);
}

TEST_P(Interop, EveryMessageArrivesIntact) {
  // Subscriptions first, then one match to know both buses are up.
  r_->subscribe_deposits(7);
  r_->subscribe_halos(std::vector<core::RegionId>{3}, 4);
  r_->subscribe_home_states(3);
  r_->join_uav(5, 3);  // the reader is UAV 5 for views
  r_->subscribe_ground();
  r_->subscribe_broadcasts();
  r_->subscribe_clock();
  r_->subscribe_phase_done();
  r_->subscribe_uav_reports(3);
  r_->subscribe_commands();
  r_->subscribe_uplinks(3);  // and a place agent relaying for its UAVs
  w_->offer_deposits(std::vector<core::RegionId>{7});
  const auto deadline = Clock::now() + std::chrono::seconds(15);
  while (w_->matched_deposit_readers(7) == 0 && Clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(w_->matched_deposit_readers(7), 1U);
  // The other topics need no wait: every endpoint is transient-local, so a
  // sample written before its reader matched still arrives (wait_for polls).

  // A forwarded batch: both deposits arrive, in order, each as it was written.
  const core::DepositMsg dep{11, 42, 9, 7, 4, 2, {-3, 17}, 0.25F, {1.5F, -0.5F, 2.0F}};
  const core::DepositMsg visit{12, 5, 9, 7, 0, 0, {4, 6}, 1.0F, {}};
  ASSERT_TRUE(w_->publish_deposits({3, 9, {dep, visit}}, 7));
  const auto deps = wait_for<core::DepositMsg>([&](auto& v) { r_->take_deposits(v); }, 2);
  ASSERT_EQ(deps.size(), 2U);
  EXPECT_EQ(deps[1].uav, 12U);
  EXPECT_EQ(deps[1].seq, 5U);
  EXPECT_EQ(deps[1].cell.x, 4);
  EXPECT_EQ(deps[1].participant, deps[0].participant);
  EXPECT_EQ(deps[0].uav, 11U);
  EXPECT_EQ(deps[0].seq, 42U);
  EXPECT_EQ(deps[0].tick, 9U);
  EXPECT_EQ(deps[0].region, 7U);
  EXPECT_EQ(deps[0].kind, 4);
  EXPECT_EQ(deps[0].layer, 2);
  EXPECT_EQ(deps[0].cell.x, -3);
  EXPECT_EQ(deps[0].cell.y, 17);
  EXPECT_EQ(deps[0].amount, 0.25F);
  EXPECT_EQ(deps[0].spread, dep.spread);

  core::TileMsg tile{3, {2, 5}, 77, 7, 4, 2, {0.5F, 1.0F, -2.0F, 3.25F, 0.0F, 1e-6F, 7.0F, 8.0F}};
  ASSERT_TRUE(w_->publish_tile(tile));
  // Only the ground's "t.*" reader reads TileState now (UAVs read views).
  const auto tiles = wait_for<core::TileMsg>([&](auto& v) { r_->take_tiles(v); }, 1);
  ASSERT_EQ(tiles.size(), 1U);
  for (const auto& t : tiles) {
    EXPECT_EQ(t.layer, 3);
    EXPECT_EQ(t.tile.tx, 2);
    EXPECT_EQ(t.tile.ty, 5);
    EXPECT_EQ(t.tick, 77U);
    EXPECT_EQ(t.region, 7U);
    EXPECT_EQ(t.width, 4);
    EXPECT_EQ(t.height, 2);
    EXPECT_EQ(t.values, tile.values);
  }

  core::UavStateMsg st{5, 12, 1.25, -2.5, 0.125, 3.0, 6, 2, 1234567890123ULL, 99, 1ULL << 40U, 8, {3, 4}, true, 1003, 7,
                       0, {}, false, 0, {}};
  // Its uplink: two deposits travel in the state (UavStateMsg::deposits).
  st.deposits = {{5, 41, 12, 3, 4, 1, {7, -2}, 0.75F, {1.5F, -0.25F, 2.0F}}, {5, 42, 12, 1, 0, 0, {0, 9}, 1.0F, {}}};
  w_->join_uav(5, 3);
  ASSERT_TRUE(w_->publish_uav_state(st));
  // Once to the home place agent's reader ("s.3"), once relayed to the
  // ground's ("g", the ground-state topic); then a relayed departure.
  w_->subscribe_uplinks(3);
  ASSERT_TRUE(w_->relay_states(std::vector<core::UavStateMsg>{st}, 3, 0, 40));
  core::UavStateMsg gone = st;
  gone.uav = 6;
  gone.departed = true;
  gone.deposits.clear();
  // With it, the gateway's report of UAV 5's phase of tick 12 (lockstep).
  const core::PhaseDoneMsg report{
      core::process_key(core::kRoleUav, 5), 12, static_cast<uint8_t>(core::ClockPhase::Uav), 1, {{3, 2}, {9, 1}}};
  ASSERT_TRUE(w_->relay_states(std::vector<core::UavStateMsg>{gone}, 3, 0, 41, std::vector{report}));
  const auto states = wait_for<core::UavStateMsg>([&](auto& v) { r_->take_uav_states(v); }, 2);
  ASSERT_EQ(states.size(), 2U);
  // Its pose: all a view's neighbour carries (IDL Neighbour).
  const auto expect_pose = [](const core::UavStateMsg& s) {
    EXPECT_EQ(s.uav, 5U);
    EXPECT_EQ(s.tick, 12U);
    EXPECT_EQ(s.x, 1.25);
    EXPECT_EQ(s.y, -2.5);
    EXPECT_EQ(s.vx, 0.125);
    EXPECT_EQ(s.vy, 3.0);
    EXPECT_EQ(s.heading, 6);
    EXPECT_EQ(s.role, 2);
    EXPECT_EQ(s.view.x, 3);
    EXPECT_EQ(s.view.y, 4);
    EXPECT_TRUE(s.finished);
  };
  // `uplink`: a state on the UavState topics carries its deposits; nested
  // in a field it goes without them.
  const auto expect_state = [&](const core::UavStateMsg& s, bool uplink = true) {
    expect_pose(s);
    EXPECT_EQ(s.deposits_sent, 1234567890123ULL);
    EXPECT_EQ(s.tile_samples_received, 99U);
    EXPECT_EQ(s.samples_received, 1ULL << 40U);
    EXPECT_EQ(s.ticks_late, 8U);
    EXPECT_EQ(s.tick_gap_max_ms, 1003U);
    EXPECT_EQ(s.tick_gaps_over_2, 7U);
    if (!uplink) {
      EXPECT_TRUE(s.deposits.empty());
      return;
    }
    ASSERT_EQ(s.deposits.size(), 2U) << "departed " << s.departed;
    const core::DepositMsg& d = s.deposits[0];
    EXPECT_EQ(d.uav, 5U);
    EXPECT_EQ(d.seq, 41U);
    EXPECT_EQ(d.tick, 12U);
    EXPECT_EQ(d.region, 3U);
    EXPECT_EQ(d.kind, 4);
    EXPECT_EQ(d.layer, 1);
    EXPECT_EQ(d.cell.x, 7);
    EXPECT_EQ(d.cell.y, -2);
    EXPECT_EQ(d.amount, 0.75F);
    EXPECT_EQ(d.spread[0], 1.5F);
    EXPECT_EQ(d.spread[1], -0.25F);
    EXPECT_EQ(d.spread[2], 2.0F);
    EXPECT_EQ(s.deposits[1].seq, 42U);
    EXPECT_EQ(s.deposits[1].cell.y, 9);
  };
  // The home's copy carries the deposits; the relayed one, nested in the
  // place agent's batch, goes without them.
  EXPECT_EQ(std::count_if(states.begin(), states.end(), [](const auto& s) { return !s.deposits.empty(); }), 1);
  for (const auto& s : states) expect_state(s, !s.deposits.empty());
  std::vector<core::UavDeparture> departed;
  const auto until = Clock::now() + std::chrono::seconds(10);
  while (departed.empty() && Clock::now() < until) {
    std::vector<core::UavStateMsg> more;
    r_->take_uav_states(more);
    EXPECT_TRUE(more.empty()) << "a departure is not a state";
    r_->take_departed_uavs(departed);
    if (departed.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_EQ(departed.size(), 1U);
  EXPECT_EQ(departed[0].uav, 6U);
  EXPECT_EQ(departed[0].last_tick, std::optional<uint32_t>{12}) << "the relay's last state of it";
  // The report came in the departure's batch: it is taken as a PhaseDone,
  // stamped with the relaying process (judged by it, sender_judge.hpp).
  std::vector<core::PhaseDoneMsg> relayed;
  r_->take_phase_done(relayed);
  ASSERT_EQ(relayed.size(), 1U);
  EXPECT_EQ(relayed[0].process, report.process);
  EXPECT_EQ(relayed[0].tick, 12U);
  EXPECT_EQ(relayed[0].phase, static_cast<uint8_t>(core::ClockPhase::Uav));
  EXPECT_EQ(relayed[0].broadcasts, 1U);
  ASSERT_EQ(relayed[0].deposits.size(), 2U);
  EXPECT_EQ(relayed[0].deposits[1].region, 9U);
  EXPECT_EQ(relayed[0].deposits[1].count, 1U);
  EXPECT_NE(relayed[0].participant, 0U);
  EXPECT_EQ(relayed[0].participant, departed[0].participant);

  // A view, to UAV 5 only, and a field chunk: nested tiles and states.
  core::ViewMsg view{5, 33, {tile, core::TileMsg{1, {3, 5}, 0, 0, 1, 2, {4.5F, -1.0F}}}, {st, st}};
  view.deposit_ack = 61;
  view.deposit_ack_from = 40;
  ASSERT_TRUE(w_->publish_view(view));
  const auto views = wait_for<core::ViewMsg>([&](auto& v) { r_->take_views(v); });
  ASSERT_EQ(views.size(), 1U);
  EXPECT_EQ(views[0].uav, 5U);
  EXPECT_EQ(views[0].tick, 33U);
  EXPECT_EQ(views[0].deposit_ack, 61U);
  EXPECT_EQ(views[0].deposit_ack_from, 40U);
  ASSERT_EQ(views[0].tiles.size(), 2U);
  EXPECT_EQ(views[0].tiles[0].values, tile.values);
  EXPECT_EQ(views[0].tiles[0].tick, 33U);  // a view's tiles are of its tick
  EXPECT_EQ(views[0].tiles[1].layer, 1);
  EXPECT_EQ(views[0].tiles[1].tile.tx, 3);
  EXPECT_EQ(views[0].tiles[1].height, 2);
  EXPECT_EQ(views[0].tiles[1].values, (std::vector<float>{4.5F, -1.0F}));
  // A view's neighbours (IDL Neighbour) carry what the reading UAV uses of
  // a state - its pose, the cell it reads next, whether it finished - and
  // none of its accounting.
  ASSERT_EQ(views[0].uavs.size(), 2U);
  for (const auto& s : views[0].uavs) {
    expect_pose(s);
    EXPECT_EQ(s.deposits_sent, 0U);
    EXPECT_EQ(s.samples_received, 0U);
    EXPECT_EQ(s.tick_gap_max_ms, 0U);
    EXPECT_TRUE(s.deposits.empty());
  }
  const core::ViewMsg other{6, 33, {tile}, {}};  // UAV 6's view: not for this reader
  ASSERT_TRUE(w_->publish_view(other));

  const core::FieldMsg field{7, 1, 2, 44, {tile}, {st}};
  ASSERT_TRUE(w_->publish_field(field));
  const auto fields = wait_for<core::FieldMsg>([&](auto& v) { r_->take_fields(v); });
  ASSERT_EQ(fields.size(), 1U);
  EXPECT_EQ(fields[0].region, 7U);
  EXPECT_EQ(fields[0].chunk, 1);
  EXPECT_EQ(fields[0].chunks, 2);
  EXPECT_EQ(fields[0].tick, 44U);
  ASSERT_EQ(fields[0].tiles.size(), 1U);
  EXPECT_EQ(fields[0].tiles[0].region, 7U);
  EXPECT_EQ(fields[0].tiles[0].tick, 44U);
  EXPECT_EQ(fields[0].tiles[0].values, tile.values);
  ASSERT_EQ(fields[0].uavs.size(), 1U);
  expect_state(fields[0].uavs[0], false);

  // A UAV's detection, up to its gateway; the gateway's relay, to the ground.
  ASSERT_TRUE(w_->publish_detection({5, 13, 2, {8, -1}}));
  const auto up = wait_for<core::DetectionMsg>([&](auto& v) { r_->take_uplink_detections(v); });
  ASSERT_EQ(up.size(), 1U);
  EXPECT_EQ(up[0].tick, 13U);
  ASSERT_TRUE(w_->relay_detection(up[0]));
  const auto dets = wait_for<core::DetectionMsg>([&](auto& v) { r_->take_detections(v); });
  ASSERT_EQ(dets.size(), 1U);
  EXPECT_EQ(dets[0].target, 2);
  EXPECT_EQ(dets[0].cell.x, 8);
  EXPECT_EQ(dets[0].cell.y, -1);

  ASSERT_TRUE(w_->publish_target_event({7, 14, 2, {4, 4}, 321}));
  const auto evs = wait_for<core::TargetEventMsg>([&](auto& v) { r_->take_target_events(v); });
  ASSERT_EQ(evs.size(), 1U);
  EXPECT_EQ(evs[0].region, 7U);
  EXPECT_EQ(evs[0].kind, 2);
  EXPECT_EQ(evs[0].response_ticks, 321U);

  core::HealthMsg health{7, 15, 25.5F, 100, 90, 10, 3, true, 250, 2};
  health.linked = true;
  health.life = 3;
  ASSERT_TRUE(w_->publish_health(health));
  const auto hs = wait_for<core::HealthMsg>([&](auto& v) { r_->take_health(v); });
  ASSERT_EQ(hs.size(), 1U);
  EXPECT_EQ(hs[0].tick_rate_hz, 25.5F);
  EXPECT_EQ(hs[0].deposits_received, 100U);
  EXPECT_EQ(hs[0].deposits_applied, 90U);
  EXPECT_EQ(hs[0].deposits_rejected, 10U);
  EXPECT_EQ(hs[0].halos_missing, 3U);
  EXPECT_TRUE(hs[0].finished);
  EXPECT_EQ(hs[0].tick_gap_max_ms, 250U);
  EXPECT_EQ(hs[0].tick_gaps_over_2, 2U);
  EXPECT_TRUE(hs[0].linked);
  EXPECT_EQ(hs[0].life, 3U);

  // Two replicas' rings of one region and tick (shared ownership): the
  // replica is part of the key, so neither replaces the other in the
  // keep-last-1 histories (docs/faults.md, "Hot-standby place agents").
  ASSERT_TRUE(w_->publish_halo({3, 16, {1.0F, 2.0F, 3.0F}, {0.0F, 9.0F}, 0}, 4));
  ASSERT_TRUE(w_->publish_halo({3, 16, {4.0F, 5.0F, 6.0F}, {7.0F, 8.0F}, 1}, 4));
  auto halos = wait_for<core::HaloMsg>([&](auto& v) { r_->take_halos(v); }, 2);
  ASSERT_EQ(halos.size(), 2U);
  std::sort(halos.begin(), halos.end(), [](const auto& a, const auto& b) { return a.replica < b.replica; });
  EXPECT_EQ(halos[0].region, 3U);
  EXPECT_EQ(halos[0].tick, 16U);
  EXPECT_EQ(halos[0].replica, 0U);
  EXPECT_EQ(halos[0].target, (std::vector<float>{1.0F, 2.0F, 3.0F}));
  EXPECT_EQ(halos[0].obstacle, (std::vector<float>{0.0F, 9.0F}));
  EXPECT_EQ(halos[1].replica, 1U);
  EXPECT_EQ(halos[1].target, (std::vector<float>{4.0F, 5.0F, 6.0F}));
  EXPECT_EQ(halos[1].obstacle, (std::vector<float>{7.0F, 8.0F}));

  // A UAV's broadcast up to its gateway, the gateway's relay to the swarm.
  ASSERT_TRUE(w_->publish_broadcast({5, 17, 1, {1.5, -2.25, 1e300}}));
  const auto bup = wait_for<core::BroadcastMsg>([&](auto& v) { r_->take_uplink_broadcasts(v); });
  ASSERT_EQ(bup.size(), 1U);
  ASSERT_TRUE(w_->relay_broadcast_up(bup[0]));
  const auto bcs = wait_for<core::BroadcastMsg>([&](auto& v) { r_->take_broadcasts(v); });
  ASSERT_EQ(bcs.size(), 1U);
  EXPECT_EQ(bcs[0].kind, 1);
  EXPECT_EQ(bcs[0].values, (std::vector<double>{1.5, -2.25, 1e300}));

  core::ClockMsg clk;
  clk.tick = 18;
  clk.phase = 1;
  clk.broadcasts = 4;
  clk.occupancy = {{{1, 2}, 3}, {{4, 5}, 6}};
  clk.deposits = {{0, 10}, {7, 20}};
  clk.absent = {2, 9};
  clk.states = {{1, 3}, {6, 2}};
  clk.next_uav_phase = true;
  ASSERT_TRUE(w_->publish_clock(clk));
  const auto clks = wait_for<core::ClockMsg>([&](auto& v) { r_->take_clock(v); });
  ASSERT_EQ(clks.size(), 1U);
  EXPECT_EQ(clks[0].tick, 18U);
  EXPECT_EQ(clks[0].phase, 1);
  EXPECT_EQ(clks[0].broadcasts, 4U);
  ASSERT_EQ(clks[0].occupancy.size(), 2U);
  EXPECT_EQ(clks[0].occupancy[1].tile.tx, 4);
  EXPECT_EQ(clks[0].occupancy[1].tile.ty, 5);
  EXPECT_EQ(clks[0].occupancy[1].count, 6U);
  ASSERT_EQ(clks[0].deposits.size(), 2U);
  EXPECT_EQ(clks[0].deposits[1].region, 7U);
  EXPECT_EQ(clks[0].deposits[1].count, 20U);
  EXPECT_EQ(clks[0].absent, (std::vector<core::RegionId>{2, 9}));
  ASSERT_EQ(clks[0].states.size(), 2U);
  EXPECT_EQ(clks[0].states[1].region, 6U);
  EXPECT_EQ(clks[0].states[1].count, 2U);
  EXPECT_TRUE(clks[0].next_uav_phase);

  // The writer joined as UAV 5, homed on 3: in the lockstep tree its report
  // goes to place agent 3's reader, not to the conductor's.
  w_->join_clock_tree(std::vector<core::RegionId>{3, 4});
  ASSERT_TRUE(w_->publish_phase_done({(1U << 24) | 5U, 18, 0, 1, {{7, 3}, {8, 1}}}));
  const auto dones = wait_for<core::PhaseDoneMsg>([&](auto& v) { r_->take_uav_reports(v); });
  ASSERT_EQ(dones.size(), 1U);
  EXPECT_EQ(dones[0].process, (1U << 24) | 5U);
  EXPECT_EQ(dones[0].tick, 18U);
  EXPECT_EQ(dones[0].broadcasts, 1U);
  ASSERT_EQ(dones[0].deposits.size(), 2U);
  EXPECT_EQ(dones[0].deposits[0].region, 7U);
  EXPECT_EQ(dones[0].deposits[0].count, 3U);

  core::CommandMsg cmd;
  cmd.issuer = 3U << 24U;
  cmd.seq = 42;
  cmd.issued_ms = 0xFEDCBA9876543210ULL;
  cmd.kind = 3;
  cmd.x = -5;
  cmd.y = 7;
  cmd.w = 3;
  cmd.h = 2;
  for (std::size_t i = 0; i < cmd.mac.size(); ++i) cmd.mac[i] = static_cast<uint8_t>(255 - 7 * i);
  ASSERT_TRUE(w_->publish_command(cmd));
  const auto cmds = wait_for<core::CommandMsg>([&](auto& v) { r_->take_commands(v); });
  ASSERT_EQ(cmds.size(), 1U);
  EXPECT_EQ(cmds[0].issuer, cmd.issuer);
  EXPECT_EQ(cmds[0].seq, 42U);
  EXPECT_EQ(cmds[0].issued_ms, cmd.issued_ms);
  EXPECT_EQ(cmds[0].kind, 3);
  EXPECT_EQ(cmds[0].x, -5);
  EXPECT_EQ(cmds[0].y, 7);
  EXPECT_EQ(cmds[0].w, 3);
  EXPECT_EQ(cmds[0].h, 2);
  EXPECT_EQ(cmds[0].mac, cmd.mac);

  EXPECT_EQ(r_->stats().samples_dropped, 0U);
  // UAV 6's view never reached UAV 5 (its partition is "u.6").
  std::vector<core::ViewMsg> stray;
  r_->take_views(stray);
  EXPECT_TRUE(stray.empty());
}

// Who wrote it (issue 28, core/place_vouch.hpp): every sample a bus takes
// names its writer's process, the same for every writer of one process
// whichever vendor reads it, and another process's differs.
TEST_P(Interop, EverySampleNamesItsWritersProcessTheSameForEachOfItsWriters) {
  r_->subscribe_deposits(7);
  r_->subscribe_ground();
  w_->offer_deposits(std::vector<core::RegionId>{7});
  const auto deadline = Clock::now() + std::chrono::seconds(15);
  while (w_->matched_deposit_readers(7) == 0 && Clock::now() < deadline) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(w_->matched_deposit_readers(7), 1U);
  ASSERT_TRUE(w_->publish_deposit({11, 42, 9, 7, 4, 2, {-3, 17}, 0.25F, {}}, 7));
  ASSERT_TRUE(w_->publish_tile({0, {2, 5}, 77, 7, 1, 1, {0.5F}}));
  auto other = make(GetParam().writer, "other");
  ASSERT_TRUE(other);
  ASSERT_TRUE(other->publish_tile({0, {3, 5}, 77, 7, 1, 1, {0.5F}}));
  const auto deps = wait_for<core::DepositMsg>([&](auto& v) { r_->take_deposits(v); });
  const auto tiles = wait_for<core::TileMsg>([&](auto& v) { r_->take_tiles(v); }, 2);
  ASSERT_EQ(deps.size(), 1U);
  ASSERT_EQ(tiles.size(), 2U);
  const auto& mine = tiles[0].tile.tx == 2 ? tiles[0] : tiles[1];
  const auto& theirs = tiles[0].tile.tx == 2 ? tiles[1] : tiles[0];
  EXPECT_NE(deps[0].participant, 0U);
  EXPECT_EQ(mine.participant, deps[0].participant) << "two writers of one process";
  EXPECT_NE(theirs.participant, 0U);
  EXPECT_NE(theirs.participant, deps[0].participant) << "another process";
}

TEST_P(Interop, SamplesOverTheIdlBoundsAreRefusedBeforeWriting) {
  core::TileMsg tile{0, {0, 0}, 1, 0, 40, 40, std::vector<float>(1600, 1.0F)};
  EXPECT_FALSE(w_->publish_tile(tile));
  EXPECT_FALSE(w_->publish_broadcast({0, 1, 0, std::vector<double>(65, 0.0)}));
  EXPECT_FALSE(w_->publish_halo({0, 1, std::vector<float>(4097, 0.0F), {}}, 1));
  core::ViewMsg view{0, 1, std::vector<core::TileMsg>(1025), {}};
  EXPECT_FALSE(w_->publish_view(view));
  core::FieldMsg field{0, 0, 1, 1, std::vector<core::TileMsg>(257), {}};
  EXPECT_FALSE(w_->publish_field(field));
  field.tiles = {tile};  // a tile over its own bound inside a field
  EXPECT_FALSE(w_->publish_field(field));
  EXPECT_FALSE(w_->publish_deposits({0, 1, std::vector<core::DepositMsg>(core::kMaxForwardDeposits + 1)}, 0));
  EXPECT_EQ(w_->stats().writes_refused, 7U);
  EXPECT_EQ(w_->stats().writes_failed, 0U);
}

TEST_P(Interop, ThePublishedRunReachesAReaderThatJoinsLaterIntact) {
  // A place agent publishes the run once; a monitor subscribes afterwards
  // (transient-local) and gets the scenario text byte for byte.
  core::ScenarioMsg run;
  run.publisher = core::place_id(3, 1);
  for (int i = 0; i < 3000; ++i) run.text += static_cast<char>('a' + i % 26);  // over one small datagram
  run.text += "\n# non-ASCII: \xc3\xa9\n";
  run.uavs = 250;
  run.ticks = 1200;
  run.seed = 0x123456789ULL;
  run.tick_rate_hz = 12.5;
  run.clock = 1;
  run.lease_ms = 1500;
  run.standby = true;
  run.shared_ownership = true;
  // Written before the reader exists: a late joiner gets it (transient-local).
  ASSERT_TRUE(w_->publish_scenario(run));
  r_->subscribe_scenario();
  const auto got = wait_for<core::ScenarioMsg>([&](auto& v) { r_->take_scenarios(v); });
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].publisher, run.publisher);
  EXPECT_EQ(got[0].text, run.text);
  EXPECT_EQ(got[0].uavs, 250U);
  EXPECT_EQ(got[0].ticks, 1200U);
  EXPECT_EQ(got[0].seed, run.seed);
  EXPECT_DOUBLE_EQ(got[0].tick_rate_hz, 12.5);
  EXPECT_EQ(got[0].clock, 1);
  EXPECT_EQ(got[0].lease_ms, 1500U);
  EXPECT_TRUE(got[0].standby);
  EXPECT_TRUE(got[0].shared_ownership);
  core::ScenarioMsg big = run;
  big.text.assign(core::kMaxScenarioBytes + 1, 'x');
  EXPECT_FALSE(w_->publish_scenario(big));
  EXPECT_EQ(w_->stats().writes_refused, 1U);
}

INSTANTIATE_TEST_SUITE_P(Vendors, Interop,
                         testing::Values(Pair{"cyclone", "cyclone"}, Pair{"fastdds", "fastdds"}, Pair{"cyclone", "fastdds"},
                                         Pair{"fastdds", "cyclone"}),
                         pair_name);

// A realtime swarm's views are best effort (bus/qos.hpp, Pacing): written
// every tick, they reach the UAV across vendors once matched; one written
// before the match is not kept for it (volatile).
class RealtimeViews : public testing::TestWithParam<Pair> {};

TEST_P(RealtimeViews, AViewWrittenEachTickReachesItsUavAcrossVendorsBestEffort) {
  bus::BusOptions o;
  o.domain = 66;
  o.pacing = bus::Pacing::Realtime;
  o.process_name = "place";
  auto w = bus::make_bus(GetParam().writer, o);
  o.process_name = "uav-5";
  auto r = bus::make_bus(GetParam().reader, o);
  ASSERT_TRUE(w && r);
  r.value()->join_uav(5, 3);
  core::ViewMsg view{5, 0, {}, {}};
  view.deposit_ack = 7;
  std::vector<core::ViewMsg> got;
  const auto deadline = Clock::now() + std::chrono::seconds(15);
  while (got.empty() && Clock::now() < deadline) {
    ++view.tick;  // a tick's view, as a realtime place agent writes them
    ASSERT_TRUE(w.value()->publish_view(view));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    r.value()->take_views(got);
  }
  ASSERT_FALSE(got.empty()) << "no view in 15 s";
  EXPECT_EQ(got.back().uav, 5U);
  EXPECT_EQ(got.back().deposit_ack, 7U);
  EXPECT_GE(got.back().tick, 1U);
}

INSTANTIATE_TEST_SUITE_P(Vendors, RealtimeViews,
                         testing::Values(Pair{"cyclone", "cyclone"}, Pair{"fastdds", "fastdds"},
                                         Pair{"cyclone", "fastdds"}, Pair{"fastdds", "cyclone"}),
                         pair_name);

TEST(Peers, AddressesAreKeptNamesResolveToTheirAddressesAndUnknownNamesAreListed) {
  const auto p = bus::resolve_peers(" 10.0.0.2, localhost,10.0.0.2,,no-such-host.invalid ");
  ASSERT_TRUE(static_cast<bool>(p)) << p.error().message;
  ASSERT_EQ(p->addresses.size(), 2U);  // the repeated address once
  EXPECT_EQ(p->addresses[0], "10.0.0.2");
  EXPECT_EQ(p->addresses[1], "127.0.0.1");
  ASSERT_EQ(p->unresolved.size(), 1U);
  EXPECT_EQ(p->unresolved[0], "no-such-host.invalid");
  const auto bad = bus::resolve_peers("10.0.0.1:7400");
  ASSERT_FALSE(static_cast<bool>(bad));
  EXPECT_NE(bad.error().message.find("10.0.0.1:7400"), std::string::npos);
  EXPECT_TRUE(bus::resolve_peers("")->addresses.empty());
}

TEST(Peers, OnlyTheLanProfilesTakePeersAndABusComesUpWithThem) {
  bus::BusOptions o;
  o.domain = 60;
  o.profile = "onehost";
  o.peers = {"127.0.0.1"};
  for (const char* vendor : {"cyclone", "fastdds"}) {
    o.profile = "onehost";
    const auto refused = bus::make_bus(vendor, o);
    ASSERT_FALSE(static_cast<bool>(refused)) << vendor;
    EXPECT_NE(refused.error().message.find("lan and lan-unicast"), std::string::npos) << refused.error().message;
    o.profile = "lan-unicast";
    const auto ok = bus::make_bus(vendor, o);
    EXPECT_TRUE(static_cast<bool>(ok)) << vendor << ": " << (ok ? "" : ok.error().message);
  }
}

TEST(Bus, MixedIsNotAProcessVendorAndUnknownVendorsAreNamed) {
  const auto m = bus::make_bus("mixed", {});
  ASSERT_FALSE(static_cast<bool>(m));
  EXPECT_NE(m.error().message.find("pheromesh run"), std::string::npos);
  const auto u = bus::make_bus("opendds", {});
  ASSERT_FALSE(static_cast<bool>(u));
  EXPECT_NE(u.error().message.find("cyclone, fastdds"), std::string::npos);
}

}  // namespace

namespace {

class Departure : public testing::TestWithParam<Pair> {};

TEST_P(Departure, AReaderDeletedByOneVendorIsForgottenByTheOthersWriters) {
  // A process that leaves (or dies) deletes its readers; a place agent's
  // writer must stop waiting for their acknowledgements (flush) soon after.
  auto w = make(GetParam().writer, "writer");
  auto r = make(GetParam().reader, "reader");
  ASSERT_TRUE(w && r);
  r->subscribe_fields();
  const core::FieldMsg field{0, 0, 1, 1, {core::TileMsg{0, {2, 5}, 1, 0, 1, 1, {1.0F}}}, {}};
  ASSERT_TRUE(w->publish_field(field));
  ASSERT_EQ(wait_for<core::FieldMsg>([&](auto& v) { r->take_fields(v); }).size(), 1U);
  ASSERT_TRUE(w->flush(std::chrono::seconds(5)));
  r.reset();
  bool acked = false;
  const auto deadline = Clock::now() + std::chrono::seconds(10);
  for (uint32_t tick = 2; !acked && Clock::now() < deadline; ++tick) {
    core::FieldMsg next = field;
    next.tick = tick;
    ASSERT_TRUE(w->publish_field(next));
    acked = w->flush(std::chrono::milliseconds(200));
  }
  EXPECT_TRUE(acked) << "the writer still waits for the deleted reader";
}

TEST_P(Departure, AWaitReturnsWhenDataArrivesAndNotBefore) {
  // The wait set: a wait on a kind with nothing to take runs to its
  // deadline; a sample of that kind ends it early.
  auto w = make(GetParam().writer, "writer");
  auto r = make(GetParam().reader, "reader");
  ASSERT_TRUE(w && r);
  r->subscribe_fields();
  r->subscribe_broadcasts();
  const auto t0 = Clock::now();
  EXPECT_FALSE(r->wait({bus::TopicKind::Field}, t0 + std::chrono::milliseconds(300)));
  EXPECT_GE(Clock::now() - t0, std::chrono::milliseconds(290));
  ASSERT_TRUE(w->publish_field({0, 0, 1, 7, {}, {}}));
  ASSERT_TRUE(w->publish_broadcast({1, 2, 0, {1.0}}));
  // Ends by data (true), well before the deadline of 20 s.
  EXPECT_TRUE(r->wait({bus::TopicKind::Field}, Clock::now() + std::chrono::seconds(20)));
  std::vector<core::FieldMsg> got;
  const auto deadline = Clock::now() + std::chrono::seconds(20);
  while (got.empty() && Clock::now() < deadline) {
    r->wait({bus::TopicKind::Field}, deadline);
    r->take_fields(got);
  }
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].tick, 7U);
}

TEST_P(Departure, OnDataCallsBackInTheVendorsThreadForTheNamedKindsOnlyUntilRemovedAndCreatesNoEndpoint) {
  // bus::Bus::on_data, as a lockstep UAV and place agent answer in the
  // receive thread: the callback runs in the thread that delivers the
  // sample, for a sample of a kind it names, and the reader still holds the
  // sample for a take there; a kind it does not name calls nothing; once
  // removed, nothing calls it any more. A writer not opened before is
  // refused there (Fast DDS 2.9 deadlocked creating it), and opened
  // outside.
  auto w = make(GetParam().writer, "writer");
  auto r = make(GetParam().reader, "reader");
  ASSERT_TRUE(w && r);
  r->subscribe_fields();
  r->subscribe_broadcasts();
  std::mutex m;
  std::condition_variable called;
  std::vector<core::FieldMsg> taken;
  std::vector<std::thread::id> threads;
  std::size_t refused = 0;  // health writers refused in the callback
  const std::vector<bus::TopicKind> kinds{bus::TopicKind::Field};
  ASSERT_TRUE(r->on_data(kinds, [&] {
    {
      std::lock_guard<std::mutex> lock(m);
      threads.push_back(std::this_thread::get_id());
      r->take_fields(taken);
      try {
        r->publish_health({});
      } catch (const bus::BusMisuse&) {
        ++refused;
      }
    }
    called.notify_all();
  }));
  ASSERT_TRUE(w->publish_broadcast({1, 2, 0, {1.0}}));
  ASSERT_TRUE(w->publish_field({0, 0, 1, 7, {}, {}}));
  {
    std::unique_lock<std::mutex> lock(m);
    ASSERT_TRUE(called.wait_for(lock, std::chrono::seconds(20), [&] { return !taken.empty(); }))
        << "the callback took no field in 20 s";
    ASSERT_EQ(taken.size(), 1U);
    EXPECT_EQ(taken[0].tick, 7U);
    // Across vendors the sample came over UDP: a receive thread of the
    // reader's vendor. (One vendor delivers to a reader of the same process
    // in the writer's thread, here the test's.)
    if (GetParam().writer != GetParam().reader) {
      for (const auto& t : threads) EXPECT_NE(t, std::this_thread::get_id());
    }
  }
  const auto broadcasts = wait_for<core::BroadcastMsg>([&](auto& v) { r->take_broadcasts(v); });
  EXPECT_EQ(broadcasts.size(), 1U) << "a kind not named stays for take";
  ASSERT_TRUE(r->on_data({}, {}));
  std::size_t calls = 0;
  {
    std::lock_guard<std::mutex> lock(m);
    calls = threads.size();
  }
  ASSERT_TRUE(w->publish_field({0, 0, 1, 8, {}, {}}));
  const auto later = wait_for<core::FieldMsg>([&](auto& v) { r->take_fields(v); });
  ASSERT_EQ(later.size(), 1U);
  EXPECT_EQ(later[0].tick, 8U);
  std::lock_guard<std::mutex> lock(m);
  EXPECT_EQ(threads.size(), calls) << "called after it was removed";
  EXPECT_EQ(refused, calls) << "a writer created in the callback";
  EXPECT_TRUE(r->publish_health({})) << "outside a callback it is opened";
}

TEST_P(Departure, LockstepResenderWritesTheTicksSamplesAgainAfterAQuietSpellOnly) {
  // bus::LatestResender: publishes and remembers; once nothing was
  // published for its quiet period it writes the same samples again (a new
  // sample of the same instance and content); begin_tick forgets them.
  auto w = make(GetParam().writer, "writer");
  auto r = make(GetParam().reader, "reader");
  ASSERT_TRUE(w && r);
  r->subscribe_fields();
  r->subscribe_phase_done();
  // Its own clock, moved by the test: "quiet for a second" without a second's sleep.
  auto now = std::make_shared<Clock::time_point>(Clock::now());
  const bus::LatestResender::Now clock = [now] { return *now; };
  bus::LatestResender resend(*w, true, std::chrono::milliseconds(1000), clock);
  EXPECT_FALSE(resend.resend_if_quiet()) << "nothing remembered yet";
  const core::FieldMsg field{3, 0, 1, 9, {core::TileMsg{0, {2, 5}, 1, 0, 9, 1, {1.0F}}}, {}};
  ASSERT_TRUE(resend.field(field));
  ASSERT_TRUE(resend.phase_done({core::process_key(core::kRolePlace, 3), 9, 2, 0, {}}));
  EXPECT_FALSE(resend.resend_if_quiet()) << "published just now";
  const auto fields = wait_for<core::FieldMsg>([&](auto& v) { r->take_fields(v); });
  ASSERT_EQ(fields.size(), 1U);
  *now += std::chrono::milliseconds(999);
  EXPECT_FALSE(resend.resend_if_quiet()) << "quiet for less than the period";
  *now += std::chrono::milliseconds(1);
  EXPECT_TRUE(resend.resend_if_quiet());
  EXPECT_EQ(resend.resends(), 1U);
  const auto again = wait_for<core::FieldMsg>([&](auto& v) { r->take_fields(v); });
  ASSERT_EQ(again.size(), 1U);
  EXPECT_EQ(again[0].region, 3U);
  EXPECT_EQ(again[0].tick, 9U);
  ASSERT_EQ(again[0].tiles.size(), 1U);
  EXPECT_EQ(again[0].tiles[0].tile.ty, 5);
  std::vector<core::PhaseDoneMsg> dones;
  const auto deadline = Clock::now() + std::chrono::seconds(20);
  while (dones.empty() && Clock::now() < deadline) {
    r->wait({bus::TopicKind::PhaseDone}, Clock::now() + std::chrono::milliseconds(100));
    r->take_phase_done(dones);
  }
  ASSERT_FALSE(dones.empty());
  EXPECT_EQ(dones.back().tick, 9U);
  // A new tick forgets the old samples; what it remembers in their place is
  // re-sent, and only that.
  resend.begin_tick();
  *now += std::chrono::seconds(2);
  EXPECT_FALSE(resend.resend_if_quiet());
  const core::FieldMsg next{3, 0, 1, 10, {core::TileMsg{0, {2, 6}, 10, 0, 9, 1, {2.0F}}}, {}};
  ASSERT_TRUE(resend.field(next));
  ASSERT_EQ(wait_for<core::FieldMsg>([&](auto& v) { r->take_fields(v); }).size(), 1U);
  *now += std::chrono::seconds(1);
  EXPECT_TRUE(resend.resend_if_quiet());
  const auto latest = wait_for<core::FieldMsg>([&](auto& v) { r->take_fields(v); });
  ASSERT_EQ(latest.size(), 1U);
  EXPECT_EQ(latest[0].tick, 10U);
  ASSERT_EQ(latest[0].tiles.size(), 1U);
  EXPECT_EQ(latest[0].tiles[0].tile.ty, 6);
  EXPECT_EQ(latest[0].tiles[0].values, std::vector<float>{2.0F});
  // A disabled resender only publishes.
  bus::LatestResender off(*w, false, std::chrono::milliseconds(1), clock);
  ASSERT_TRUE(off.field(field));
  *now += std::chrono::milliseconds(5);
  EXPECT_FALSE(off.resend_if_quiet());
  EXPECT_EQ(off.resends(), 0U);
}

INSTANTIATE_TEST_SUITE_P(Vendors, Departure,
                         testing::Values(Pair{"cyclone", "cyclone"}, Pair{"fastdds", "fastdds"}, Pair{"cyclone", "fastdds"},
                                         Pair{"fastdds", "cyclone"}),
                         pair_name);

}  // namespace
