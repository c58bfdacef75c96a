// The in-memory bus (bus/memory.hpp): the same Bus, role wiring and typed
// endpoints as the DDS vendors, in one process without DDS. Several buses of
// one MemoryDomain play the processes of a small swarm.
#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/memory.hpp"
#include "pheromesh/bus/resend.hpp"
#include "pheromesh/bus/typed.hpp"
#include "pheromesh/auth/control.hpp"
#include "pheromesh/runtime/commands.hpp"

#include <spdlog/spdlog.h>
#include <cstdlib>

namespace pheromesh::bus {
namespace {

using Clock = std::chrono::steady_clock;

core::DepositMsg deposit(uint32_t uav, uint32_t seq, core::RegionId region) {
  return {uav, seq, 4, region, static_cast<uint8_t>(core::DepositKind::LayerAdd), 1, {3, 5}, 0.5F, {}};
}

core::UavStateMsg state(uint32_t uav, uint32_t tick) {
  core::UavStateMsg s;
  s.uav = uav;
  s.tick = tick;
  s.x = 2.5;
  return s;
}

class MemoryBus : public testing::Test {
 protected:
  std::shared_ptr<MemoryDomain> domain_ = make_memory_domain();
};

// UAV 4 with its home (place agent 1) and its backup (2), and a control key
// in the environment for the UAV's commands (removed at the end).
struct Gateways {
  explicit Gateways(const std::shared_ptr<MemoryDomain>& domain)
      : hex(auth::random_control_key_hex()),
        key((::setenv(auth::kControlKeyEnv, hex.c_str(), 1), auth::parse_control_key(hex).value())),
        place1(make_memory_bus(domain)),
        place2(make_memory_bus(domain)),
        uav(make_memory_bus(domain)) {
    place1->subscribe_uplinks(1);
    place2->subscribe_uplinks(2);
    uav->join_uav(4, 1);
    uav->join_gateways(std::vector<core::RegionId>{1, 2});
  }
  ~Gateways() { ::unsetenv(auth::kControlKeyEnv); }
  Gateways(const Gateways&) = delete;
  Gateways& operator=(const Gateways&) = delete;
  std::string hex;
  auth::ControlKey key;
  std::unique_ptr<Bus> place1, place2, uav;
};

TEST_F(MemoryBus, APlaceAgentSeesItsTileAndRingReadersMatchedBeforeItWritesToThem) {
  // What a place agent's Ready waits for besides its deposit readers
  // (PlaceApp::note_linked): the other region's tiles reader and its
  // neighbour's ring reader, counted on writers opened before flying.
  auto place1 = make_memory_bus(domain_);
  auto place2 = make_memory_bus(domain_);
  const std::vector<core::RegionId> to2{2};
  place1->offer_place_exchange(to2, /*served=*/false);
  place1->offer_halos(to2, 1);
  EXPECT_EQ(place1->matched_tile_readers(2), 0U);
  EXPECT_EQ(place1->matched_halo_readers(1, 2), 0U);
  place2->subscribe_place_exchange(2, /*served=*/false);
  EXPECT_EQ(place1->matched_tile_readers(2), 1U);
  EXPECT_EQ(place1->matched_halo_readers(1, 2), 0U) << "2 reads no ring of 1 yet";
  const std::vector<core::RegionId> from1{1};
  place2->subscribe_halos(from1, 2);
  EXPECT_EQ(place1->matched_halo_readers(1, 2), 1U);
  EXPECT_EQ(place1->matched_tile_readers(3), 0U) << "no writer for region 3";
}

TEST_F(MemoryBus, AUavsDepositsTravelInItsStateToItsHomeWhichForwardsThoseOfAnotherRegionToItsOwner) {
  auto uav = make_memory_bus(domain_);
  auto place1 = make_memory_bus(domain_);
  auto place2 = make_memory_bus(domain_);
  place1->subscribe_home_states(1);
  place2->subscribe_home_states(2);
  place2->subscribe_deposits(2);
  uav->join_uav(7, 1);
  EXPECT_EQ(uav->matched_state_readers(), 1U);
  EXPECT_EQ(uav->matched_deposit_readers(1), 0U) << "a UAV has no deposit writer: its deposits go in its state";
  core::UavStateMsg s = state(7, 4);
  s.deposits = {deposit(7, 1, 1), deposit(7, 2, 2)};
  ASSERT_TRUE(uav->publish_uav_state(s));
  std::vector<core::UavStateMsg> at1, at2;
  place1->take_uav_states(at1);
  place2->take_uav_states(at2);
  ASSERT_EQ(at1.size(), 1U);
  ASSERT_EQ(at1[0].deposits.size(), 2U);
  EXPECT_EQ(at1[0].deposits[0].seq, 1U);
  EXPECT_EQ(at1[0].deposits[0].cell.y, 5);
  EXPECT_EQ(at1[0].deposits[1].region, 2U);
  EXPECT_TRUE(at2.empty());
  // Forwarded by place agent 1 into region 2's partition, in one batch with
  // the other deposit of this take for region 2: now 2 has both, in order,
  // each naming the forwarder's process.
  place1->offer_deposits(std::vector<core::RegionId>{2});
  EXPECT_EQ(place1->matched_deposit_readers(2), 1U);
  ASSERT_TRUE(place1->publish_deposits({1, 4, {at1[0].deposits[1], deposit(7, 3, 2)}}, 2));
  std::vector<core::DepositMsg> got2;
  place2->take_deposits(got2);
  ASSERT_EQ(got2.size(), 2U);
  EXPECT_EQ(got2[0].seq, 2U);
  EXPECT_EQ(got2[1].seq, 3U);
  EXPECT_NE(got2[0].participant, 0U);
  EXPECT_EQ(got2[1].participant, got2[0].participant);
  EXPECT_EQ(uav->vendor(), "memory");
}

TEST_F(MemoryBus, AUavsStateReachesOnlyItsHomePlaceAgentWhichRelaysItToTheGroundStation) {
  auto uav = make_memory_bus(domain_);
  auto home = make_memory_bus(domain_);
  auto other = make_memory_bus(domain_);
  auto ground = make_memory_bus(domain_);
  home->subscribe_home_states(3);
  home->subscribe_uplinks(3);
  other->subscribe_home_states(4);
  ground->subscribe_ground();
  uav->join_uav(9, 3);
  EXPECT_EQ(uav->matched_state_readers(), 1U) << "its home only: the ground station reads the relay";
  ASSERT_TRUE(uav->publish_uav_state(state(9, 11)));
  std::vector<core::UavStateMsg> at_home, at_other, at_ground;
  home->take_uav_states(at_home);
  other->take_uav_states(at_other);
  ground->take_uav_states(at_ground);
  ASSERT_EQ(at_home.size(), 1U);
  EXPECT_EQ(at_home[0].tick, 11U);
  EXPECT_DOUBLE_EQ(at_home[0].x, 2.5);
  EXPECT_TRUE(at_other.empty());
  EXPECT_TRUE(at_ground.empty());
  ASSERT_TRUE(home->relay_states(at_home, 3, 0, 11));
  ground->take_uav_states(at_ground);
  ASSERT_EQ(at_ground.size(), 1U);
  EXPECT_EQ(at_ground[0].uav, 9U);
  EXPECT_EQ(at_ground[0].tick, 11U);
}

TEST_F(MemoryBus, AViewReachesOnlyTheUavItIsFor) {
  auto place = make_memory_bus(domain_);
  auto uav5 = make_memory_bus(domain_);
  auto uav6 = make_memory_bus(domain_);
  uav5->join_uav(5, 0);
  uav6->join_uav(6, 0);
  const std::vector<uint32_t> homed{5, 6};
  place->offer_views(homed);
  ASSERT_TRUE(place->publish_view({5, 3, {core::TileMsg{0, {1, 2}, 0, 0, 1, 1, {4.0F}}}, {}, 17}));
  std::vector<core::ViewMsg> v5, v6;
  uav5->take_views(v5);
  uav6->take_views(v6);
  ASSERT_EQ(v5.size(), 1U);
  EXPECT_EQ(v5[0].tick, 3U);
  EXPECT_EQ(v5[0].deposit_ack, 17U);
  ASSERT_EQ(v5[0].tiles.size(), 1U);
  EXPECT_EQ(v5[0].tiles[0].values, std::vector<float>{4.0F});
  EXPECT_TRUE(v6.empty());
}

TEST_F(MemoryBus, AViewsClockGoesToALockstepUavAsAClockOfThePlaceAgentsProcessAndNowhereElse) {
  auto place = make_memory_bus(domain_);
  auto lockstep = make_memory_bus(domain_);
  auto realtime = make_memory_bus(domain_);
  lockstep->join_uav(5, 3);
  lockstep->join_clock_tree(std::vector<core::RegionId>{3, 4});
  realtime->join_uav(6, 3);
  place->subscribe_uav_reports(3);  // place agent 3: its relay writers
  place->offer_views(std::vector<uint32_t>{5, 6});
  core::ClockMsg uav_clock;
  uav_clock.tick = 19;
  uav_clock.phase = static_cast<uint8_t>(core::ClockPhase::Uav);
  uav_clock.broadcasts = 2;
  uav_clock.occupancy = {{{1, 2}, 3}};
  uav_clock.absent = {6};
  for (uint32_t uav : {5U, 6U}) {
    core::ViewMsg v{uav, 18, {}, {}};
    v.clock = uav_clock;
    ASSERT_TRUE(place->publish_view(v));
  }
  // The lockstep UAV's clock comes with take_clock (which holds the view
  // for take_views); the view comes without it.
  std::vector<core::ClockMsg> clocks;
  lockstep->take_clock(clocks);
  ASSERT_EQ(clocks.size(), 1U);
  EXPECT_EQ(clocks[0].tick, 19U);
  EXPECT_EQ(clocks[0].phase, static_cast<uint8_t>(core::ClockPhase::Uav));
  EXPECT_EQ(clocks[0].broadcasts, 2U);
  ASSERT_EQ(clocks[0].occupancy.size(), 1U);
  EXPECT_EQ(clocks[0].occupancy[0].count, 3U);
  EXPECT_EQ(clocks[0].absent, std::vector<core::RegionId>{6});
  EXPECT_NE(clocks[0].writer, 0U);
  std::vector<core::ViewMsg> views;
  lockstep->take_views(views);
  ASSERT_EQ(views.size(), 1U);
  EXPECT_EQ(views[0].tick, 18U);
  EXPECT_FALSE(views[0].clock.has_value());
  // The clock the same place agent relays names the same writer: its
  // process, through either of its writers (core::LockstepFollower latches it).
  core::ClockMsg next = uav_clock;
  next.tick = 20;
  ASSERT_TRUE(place->relay_clock(next, 3));
  std::vector<core::ClockMsg> relayed;
  lockstep->take_clock(relayed);
  ASSERT_EQ(relayed.size(), 1U);
  EXPECT_EQ(relayed[0].tick, 20U);
  EXPECT_EQ(relayed[0].writer, clocks[0].writer);
  // A UAV outside the lockstep tree takes no clock from its view.
  std::vector<core::ViewMsg> plain;
  realtime->take_views(plain);
  ASSERT_EQ(plain.size(), 1U);
  EXPECT_FALSE(plain[0].clock.has_value());
  std::vector<core::ClockMsg> none;
  realtime->take_clock(none);
  EXPECT_TRUE(none.empty());
}

TEST_F(MemoryBus, ALateReaderGetsTheLatestChunkOfEachRegionsFieldOnly) {
  // Transient-local, keep-last 1 per instance (region, chunk).
  auto place = make_memory_bus(domain_);
  for (uint32_t tick = 1; tick <= 3; ++tick) {
    ASSERT_TRUE(place->publish_field({0, 0, 2, tick, {}, {}}));
    ASSERT_TRUE(place->publish_field({0, 1, 2, tick, {}, {}}));
  }
  auto late = make_memory_bus(domain_);
  late->subscribe_fields();
  std::vector<core::FieldMsg> got;
  late->take_fields(got);
  ASSERT_EQ(got.size(), 2U);
  for (const auto& f : got) EXPECT_EQ(f.tick, 3U) << "chunk " << f.chunk;
  EXPECT_NE(got[0].chunk, got[1].chunk);
}

TEST_F(MemoryBus, EveryDepositAndEveryStateIsKeptForAReaderThatTakesLate) {
  // Deposit readers and a home's state readers keep all (pheromone
  // accounting: the states carry the deposits): none is replaced.
  auto uav = make_memory_bus(domain_);
  auto forwarder = make_memory_bus(domain_);
  auto place = make_memory_bus(domain_);
  place->subscribe_deposits(0);
  place->subscribe_home_states(0);
  uav->join_uav(1, 0);
  for (uint32_t seq = 1; seq <= 5; ++seq) ASSERT_TRUE(forwarder->publish_deposit(deposit(3, seq, 0), 0));
  for (uint32_t tick = 1; tick <= 5; ++tick) {
    core::UavStateMsg s = state(1, tick);
    s.deposits = {deposit(1, tick, 0)};
    ASSERT_TRUE(uav->publish_uav_state(s));
  }
  std::vector<core::DepositMsg> got;
  place->take_deposits(got);
  ASSERT_EQ(got.size(), 5U);
  for (uint32_t i = 0; i < 5; ++i) EXPECT_EQ(got[i].seq, i + 1);
  std::vector<core::UavStateMsg> states;
  place->take_uav_states(states);
  ASSERT_EQ(states.size(), 5U);
  for (uint32_t i = 0; i < 5; ++i) {
    EXPECT_EQ(states[i].tick, i + 1);
    ASSERT_EQ(states[i].deposits.size(), 1U);
    EXPECT_EQ(states[i].deposits[0].seq, i + 1);
  }
}

TEST_F(MemoryBus, AStateOverTheUplinkBoundIsRefusedNotWritten) {
  auto uav = make_memory_bus(domain_);
  auto place = make_memory_bus(domain_);
  place->subscribe_home_states(0);
  uav->join_uav(1, 0);
  core::UavStateMsg s = state(1, 1);
  s.deposits.assign(core::kMaxUplinkDeposits + 1, deposit(1, 1, 0));
  EXPECT_FALSE(uav->publish_uav_state(s));
  EXPECT_EQ(uav->stats().writes_refused, 1U);
  std::vector<core::UavStateMsg> states;
  place->take_uav_states(states);
  EXPECT_TRUE(states.empty());
}

TEST_F(MemoryBus, TheGroundStationHearsAUavsDepartureFromItsPlaceAgentAndThatOfAPlaceReplicaWhoseBusEnded) {
  auto ground = make_memory_bus(domain_);
  ground->subscribe_ground();
  auto uav = make_memory_bus(domain_);
  auto home = make_memory_bus(domain_);
  auto replica = make_memory_bus(domain_);
  home->subscribe_home_states(1);
  home->subscribe_uplinks(1);
  uav->join_uav(12, 1);
  ASSERT_TRUE(uav->publish_uav_state(state(12, 1)));
  core::HealthMsg h;
  h.region = 1;
  h.replica = 1;
  ASSERT_TRUE(replica->publish_health(h));
  std::vector<core::UavStateMsg> states;
  std::vector<core::HealthMsg> health;
  std::vector<core::UavDeparture> uavs_gone;
  std::vector<uint32_t> places_gone;
  home->take_uav_states(states);
  home->take_departed_uavs(uavs_gone);
  ASSERT_EQ(states.size(), 1U);
  EXPECT_TRUE(uavs_gone.empty());
  ground->take_health(health);
  ground->take_departed_regions(places_gone);
  EXPECT_EQ(health.size(), 1U);
  EXPECT_TRUE(places_gone.empty());
  // The UAV ends: its home sees its writer go and relays the note; the
  // ground station takes it as a departure, not as a state.
  uav.reset();
  replica.reset();
  home->take_uav_states(states);
  home->take_departed_uavs(uavs_gone);
  ASSERT_EQ(uavs_gone, std::vector<core::UavDeparture>{12}) << "its own reader's: no relay, no tick";
  core::UavStateMsg note = states[0];
  note.departed = true;
  // One sample: the state, then the note, as the home relays one take.
  ASSERT_TRUE(home->relay_states(std::vector<core::UavStateMsg>{states[0], note}, 0, 0, 1));
  states.clear();
  uavs_gone.clear();
  ground->take_uav_states(states);
  ground->take_health(health);
  ground->take_departed_uavs(uavs_gone);
  ground->take_departed_regions(places_gone);
  ASSERT_EQ(states.size(), 1U) << "the state before the note";
  EXPECT_FALSE(states[0].departed);
  EXPECT_EQ(uavs_gone, (std::vector<core::UavDeparture>{{12, states[0].tick}})) << "with the relay's last tick";
  EXPECT_EQ(places_gone, std::vector<uint32_t>{core::place_id(1, 1)});
  // Reported once.
  ground->take_departed_uavs(uavs_gone);
  EXPECT_EQ(uavs_gone.size(), 1U);
}

TEST_F(MemoryBus, PlaceAgentsRelayAUavsDetectionsAndBroadcastsUpAndTheSwarmsBroadcastsAndCommandsDown) {
  auto ground = make_memory_bus(domain_);
  auto place1 = make_memory_bus(domain_);
  auto place2 = make_memory_bus(domain_);
  auto uav7 = make_memory_bus(domain_);  // home 1, backup 2
  auto uav8 = make_memory_bus(domain_);  // home 2, backup 3 (no place agent)
  ground->subscribe_ground();
  ground->subscribe_broadcasts();
  place1->subscribe_uplinks(1);
  place2->subscribe_uplinks(2);
  place1->subscribe_commands();
  uav7->join_uav(7, 1, /*broadcasts=*/true);
  uav7->join_gateways(std::vector<core::RegionId>{1, 2});
  uav7->subscribe_broadcasts();
  uav7->subscribe_commands();
  uav8->join_uav(8, 2, /*broadcasts=*/true);
  uav8->join_gateways(std::vector<core::RegionId>{2, 3});
  uav8->subscribe_broadcasts();
  // Up: a detection reaches its gateway only, which relays it to the ground station.
  ASSERT_TRUE(uav7->publish_detection({7, 4, 1, {5, 6}}));
  std::vector<core::DetectionMsg> d_ground, d1, d2;
  ground->take_detections(d_ground);
  place2->take_uplink_detections(d2);
  place1->take_uplink_detections(d1);
  EXPECT_TRUE(d_ground.empty());
  EXPECT_TRUE(d2.empty());
  ASSERT_EQ(d1.size(), 1U);
  ASSERT_TRUE(place1->relay_detection(d1[0]));
  ground->take_detections(d_ground);
  ASSERT_EQ(d_ground.size(), 1U);
  EXPECT_EQ(d_ground[0].target, 1);
  // A broadcast: up to its gateway, on to every place agent and the ground,
  // down to the UAVs each serves. No UAV hears another directly.
  ASSERT_TRUE(uav7->publish_broadcast({7, 4, 1, {2.0}}));
  std::vector<core::BroadcastMsg> b8, b_up1, b_up2, b_swarm1, b_swarm2, b_ground;
  uav8->take_broadcasts(b8);
  ground->take_broadcasts(b_ground);
  EXPECT_TRUE(b8.empty());
  EXPECT_TRUE(b_ground.empty());
  place1->take_uplink_broadcasts(b_up1);
  place2->take_uplink_broadcasts(b_up2);
  ASSERT_EQ(b_up1.size(), 1U);
  EXPECT_TRUE(b_up2.empty());
  ASSERT_TRUE(place1->relay_broadcast_up(b_up1[0]));
  ground->take_broadcasts(b_ground);
  place1->take_broadcasts(b_swarm1);
  place2->take_broadcasts(b_swarm2);
  EXPECT_EQ(b_ground.size(), 1U);
  EXPECT_EQ(b_swarm1.size(), 1U) << "its own relay too: its UAVs hear each other through it";
  ASSERT_EQ(b_swarm2.size(), 1U);
  ASSERT_TRUE(place2->relay_broadcast_down(b_swarm2[0]));
  uav8->take_broadcasts(b8);
  ASSERT_EQ(b8.size(), 1U);
  EXPECT_EQ(b8[0].uav, 7U);
  EXPECT_EQ(b8[0].values, std::vector<double>{2.0});
  // Down: the ground station's command reaches the place agents, not the
  // UAVs; each UAV hears it from both of its gateways.
  core::CommandMsg c;
  c.issuer = 1;
  c.seq = 5;
  ASSERT_TRUE(ground->publish_command(c));
  std::vector<core::CommandMsg> at_uav, at_place;
  uav7->take_commands(at_uav);
  EXPECT_TRUE(at_uav.empty());
  place1->take_commands(at_place);
  ASSERT_EQ(at_place.size(), 1U);
  ASSERT_TRUE(place1->relay_command(at_place[0]));
  ASSERT_TRUE(place2->relay_command(at_place[0]));
  uav7->take_commands(at_uav);
  ASSERT_EQ(at_uav.size(), 2U);
  EXPECT_EQ(at_uav[0].seq, 5U);
  // Its home dead, its detections go to its backup.
  uav7->move_uplink(2);
  ASSERT_TRUE(uav7->publish_detection({7, 9, 2, {5, 6}}));
  d1.clear();
  place1->take_uplink_detections(d1);
  place2->take_uplink_detections(d2);
  EXPECT_TRUE(d1.empty());
  ASSERT_EQ(d2.size(), 1U);
  EXPECT_EQ(d2[0].tick, 9U);
}

TEST_F(MemoryBus, TheLockstepTreeCarriesTheClockDownThroughThePlaceAgentsAndTheReportsUpThroughTheGateway) {
  auto conductor = make_memory_bus(domain_);
  auto place1 = make_memory_bus(domain_);
  auto place2 = make_memory_bus(domain_);
  auto uav = make_memory_bus(domain_);
  conductor->subscribe_phase_done();
  place1->subscribe_clock();
  place2->subscribe_clock();
  place1->subscribe_uav_reports(1);
  place2->subscribe_uav_reports(2);
  uav->join_uav(7, 1);
  EXPECT_EQ(uav->matched_report_readers(), 0U) << "not in the tree yet (a realtime UAV reports nothing)";
  uav->join_clock_tree(std::vector<core::RegionId>{1, 2});  // home 1, backup 2
  EXPECT_EQ(uav->matched_report_readers(), 1U);
  // Down: the conductor's clock reaches the place agents, not the UAV; each
  // place agent's relay reaches it.
  core::ClockMsg c;
  c.tick = 3;
  ASSERT_TRUE(conductor->publish_clock(c));
  std::vector<core::ClockMsg> clocks;
  uav->take_clock(clocks);
  EXPECT_TRUE(clocks.empty());
  place1->take_clock(clocks);
  ASSERT_EQ(clocks.size(), 1U);
  ASSERT_TRUE(place1->relay_clock(clocks[0], 1));
  ASSERT_TRUE(place2->relay_clock(clocks[0], 2));  // to the UAVs homed on 2
  clocks.clear();
  uav->take_clock(clocks);
  ASSERT_EQ(clocks.size(), 1U) << "from its home only: region 2 is its backup";
  ASSERT_TRUE(place2->relay_clock_to_backups(clocks[0], 2));
  ASSERT_TRUE(place1->relay_clock_to_backups(clocks[0], 1));  // to the UAVs 1 backs up
  uav->take_clock(clocks);
  ASSERT_EQ(clocks.size(), 2U) << "and from its backup, to the UAVs it backs up";
  EXPECT_NE(clocks[0].writer, clocks[1].writer);
  // Up: its report reaches its gateway only; the gateway relays it to the conductor.
  const core::PhaseDoneMsg report{core::process_key(core::kRoleUav, 7), 3, 0, 0, {{1, 2}}};
  ASSERT_TRUE(uav->publish_phase_done(report));
  std::vector<core::PhaseDoneMsg> at_conductor, at1, at2;
  conductor->take_phase_done(at_conductor);
  EXPECT_TRUE(at_conductor.empty());
  place1->take_uav_reports(at1);
  place2->take_uav_reports(at2);
  ASSERT_EQ(at1.size(), 1U);
  EXPECT_TRUE(at2.empty());
  ASSERT_TRUE(place1->publish_phase_done(at1[0]));
  conductor->take_phase_done(at_conductor);
  ASSERT_EQ(at_conductor.size(), 1U);
  EXPECT_EQ(at_conductor[0].deposits.size(), 1U);
  // Its home dead, it reports through its backup.
  uav->move_uplink(2);
  ASSERT_TRUE(uav->publish_phase_done(report));
  at1.clear();
  place1->take_uav_reports(at1);
  place2->take_uav_reports(at2);
  EXPECT_TRUE(at1.empty());
  EXPECT_EQ(at2.size(), 1U);
}

TEST_F(MemoryBus, AUavAdmitsACommandItHearsFromBothGatewaysOnceAndStillRefusesAForgedOne) {
  const Gateways g(domain_);
  runtime::SwarmCommands commands(*g.uav, spdlog::default_logger());
  core::CommandMsg pause;
  pause.issuer = 1;
  pause.seq = 1;
  pause.kind = static_cast<uint8_t>(core::CommandKind::Pause);
  auth::sign(pause, g.key);
  ASSERT_TRUE(g.place1->relay_command(pause));
  ASSERT_TRUE(g.place2->relay_command(pause));
  const auto first = commands.take();
  ASSERT_EQ(first.size(), 1U);
  EXPECT_TRUE(commands.paused());
  EXPECT_EQ(commands.rejected(), 0U) << "the second gateway's copy is no replay";
  // Later copies (a late relay) are dropped too, uncounted; a forged command
  // with the same issuer and seq is still refused and counted.
  ASSERT_TRUE(g.place2->relay_command(pause));
  core::CommandMsg forged = pause;
  forged.kind = static_cast<uint8_t>(core::CommandKind::Resume);
  ASSERT_TRUE(g.place1->relay_command(forged));
  EXPECT_TRUE(commands.take().empty());
  EXPECT_TRUE(commands.paused());
  EXPECT_EQ(commands.rejected(), 1U);
}

// e2e.Console.mixed, restart through the console: the restarted UAV heard
// "resume" (seq 3) and an obstacle (seq 4) from one gateway's history before
// "start" (seq 1) and "pause" (seq 2) from the other's, refused those two as
// out of order and never flew (the launcher stopped it 150 s later).
TEST_F(MemoryBus, AUavThatHearsTheCommandHistoryOutOfOrderStartsTakesEveryObstacleAndKeepsTheNewestPause) {
  const Gateways g(domain_);
  runtime::SwarmCommands commands(*g.uav, spdlog::default_logger());
  const auto command = [&](uint32_t seq, core::CommandKind kind) {
    core::CommandMsg c;
    c.issuer = 1;
    c.seq = seq;
    c.kind = static_cast<uint8_t>(kind);
    c.x = static_cast<int32_t>(seq);
    c.w = 1;
    c.h = 1;
    auth::sign(c, g.key);
    return c;
  };
  ASSERT_TRUE(g.place2->relay_command(command(3, core::CommandKind::Resume)));
  ASSERT_TRUE(g.place2->relay_command(command(4, core::CommandKind::Obstacle)));
  const auto newer = commands.take();
  ASSERT_EQ(newer.size(), 2U);
  EXPECT_FALSE(commands.started());
  ASSERT_TRUE(g.place1->relay_command(command(1, core::CommandKind::Start)));
  ASSERT_TRUE(g.place1->relay_command(command(2, core::CommandKind::Pause)));
  ASSERT_TRUE(g.place1->relay_command(command(3, core::CommandKind::Resume)));  // a copy
  ASSERT_TRUE(g.place1->relay_command(command(4, core::CommandKind::Obstacle)));  // a copy
  ASSERT_TRUE(g.place1->relay_command(command(0, core::CommandKind::Obstacle)));  // an obstacle older than all
  const auto older = commands.take();
  ASSERT_EQ(older.size(), 3U) << "the older obstacle, the start and the late pause; copies dropped";
  EXPECT_EQ(older[0].seq, 0U);
  EXPECT_EQ(older[1].seq, 1U);
  EXPECT_EQ(older[2].seq, 2U) << "handed on (a place agent relays it) but not applied";
  EXPECT_TRUE(commands.started());
  EXPECT_FALSE(commands.paused()) << "the resume (seq 3) stands over the pause (seq 2)";
  EXPECT_EQ(commands.rejected(), 0U);
  // Each is admitted once: a replay of the start, however late, is refused.
  ASSERT_TRUE(g.place2->relay_command(command(1, core::CommandKind::Start)));
  EXPECT_TRUE(commands.take().empty());
}

TEST_F(MemoryBus, SamplesOverTheIdlBoundsAreRefusedAndCountedBeforeAnyTransportSeesThem) {
  auto w = make_memory_bus(domain_);
  auto r = make_memory_bus(domain_);
  r->subscribe_clock();
  core::ClockMsg clock;
  clock.states.resize(core::kMaxRegionCounts + 1);
  EXPECT_FALSE(w->publish_clock(clock));
  EXPECT_FALSE(w->publish_tile({0, {0, 0}, 1, 0, 40, 40, std::vector<float>(1600, 1.0F)}));
  EXPECT_FALSE(w->publish_halo({0, 1, {}, std::vector<float>(core::kMaxRingCells + 1, 0.0F)}, 1));
  EXPECT_EQ(w->stats().writes_refused, 3U);
  EXPECT_EQ(w->stats().writes_failed, 0U);
  std::vector<core::ClockMsg> got;
  r->take_clock(got);
  EXPECT_TRUE(got.empty());
  clock.states.resize(2);  // within the bound: written
  EXPECT_TRUE(w->publish_clock(clock));
  r->take_clock(got);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].states.size(), 2U);
}

TEST_F(MemoryBus, PublishingAStateBeforeJoiningIsAMisuseOnEveryTransport) {
  auto uav = make_memory_bus(domain_);
  EXPECT_THROW(uav->publish_uav_state(state(1, 1)), BusMisuse);
  EXPECT_EQ(uav->matched_state_readers(), 0U);
}

TEST_F(MemoryBus, AClockCarriesTheIdentityOfItsWriterWhichTwoWritersDoNotShare) {
  auto conductor = make_memory_bus(domain_);
  auto forger = make_memory_bus(domain_);
  auto uav = make_memory_bus(domain_);
  uav->subscribe_clock();
  core::ClockMsg c;
  c.tick = 4;
  ASSERT_TRUE(conductor->publish_clock(c));
  ASSERT_TRUE(forger->publish_clock(c));
  std::vector<core::ClockMsg> got;
  uav->take_clock(got);
  // The reader keeps 16 clock samples (a forged one cannot hide the
  // conductor's): both arrive, each with its own writer's identity.
  ASSERT_EQ(got.size(), 2U);
  const uint64_t conductor_id = got[0].writer;
  const uint64_t forger_id = got[1].writer;
  EXPECT_NE(conductor_id, 0U);
  EXPECT_NE(forger_id, 0U);
  EXPECT_NE(conductor_id, forger_id);
  got.clear();
  ASSERT_TRUE(conductor->publish_clock(c));
  uav->take_clock(got);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].writer, conductor_id);
}

TEST_F(MemoryBus, AWaitRunsToItsDeadlineWithoutDataAndEndsWhenASampleArrives) {
  auto place = make_memory_bus(domain_);
  auto ground = make_memory_bus(domain_);
  ground->subscribe_fields();
  const auto t0 = Clock::now();
  EXPECT_FALSE(ground->wait({TopicKind::Field}, t0 + std::chrono::milliseconds(50)));
  EXPECT_GE(Clock::now() - t0, std::chrono::milliseconds(49));
  std::thread writer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    (void)place->publish_field({2, 0, 1, 8, {}, {}});
  });
  EXPECT_TRUE(ground->wait({TopicKind::Field}, Clock::now() + std::chrono::seconds(20)));
  writer.join();
  std::vector<core::FieldMsg> got;
  ground->take_fields(got);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].region, 2U);
  EXPECT_TRUE(place->flush(std::chrono::milliseconds(1)));
}

TEST_F(MemoryBus, TheLockstepResenderWritesTheTicksSamplesAgainAfterAQuietSpell) {
  auto place = make_memory_bus(domain_);
  auto other = make_memory_bus(domain_);
  other->subscribe_fields();
  // The resender's clock is the test's: the quiet spell passes without a sleep.
  auto now = std::make_shared<Clock::time_point>(Clock::now());
  LatestResender resend(*place, true, std::chrono::milliseconds(5), [now] { return *now; });
  ASSERT_TRUE(resend.field({1, 0, 1, 6, {}, {}}));
  std::vector<core::FieldMsg> got;
  other->take_fields(got);
  ASSERT_EQ(got.size(), 1U);
  *now += std::chrono::milliseconds(4);
  EXPECT_FALSE(resend.resend_if_quiet());
  *now += std::chrono::milliseconds(1);
  EXPECT_TRUE(resend.resend_if_quiet());
  other->take_fields(got);
  ASSERT_EQ(got.size(), 2U);
  EXPECT_EQ(got[1].tick, 6U);
}

TEST(TypedBus, AWriterAndAReaderOfATopicNeedNoMethodOfTheBus) {
  // What a new topic gets for free: Writer<M> / Reader<M> over any bus.
  auto domain = make_memory_domain();
  auto a = make_memory_bus(domain);
  auto b = make_memory_bus(domain);
  Reader<core::BroadcastMsg> reader(*b, {routing::kBroadcastPartition});
  Writer<core::BroadcastMsg> writer(*a);
  EXPECT_EQ(writer.matched(routing::kBroadcastPartition), 0U);  // not offered yet
  writer.offer(routing::kBroadcastPartition);
  EXPECT_EQ(writer.matched(routing::kBroadcastPartition), 1U);
  ASSERT_TRUE(writer.write({3, 9, static_cast<uint8_t>(core::BroadcastKind::TargetFound), {4.0, 5.0}}));
  EXPECT_FALSE(writer.write({3, 9, 0, std::vector<double>(core::kMaxBroadcastValues + 1, 0.0)}));
  EXPECT_EQ(a->stats().writes_refused, 1U);
  std::vector<core::BroadcastMsg> got;
  reader.take(got);
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(got[0].values, (std::vector<double>{4.0, 5.0}));
  // Routed elsewhere ("b.other"): not for this reader.
  ASSERT_TRUE(writer.write({3, 10, 0, {}}, "b.other"));
  reader.take(got);
  EXPECT_EQ(got.size(), 1U);
}

}  // namespace
}  // namespace pheromesh::bus
