// One plausibility rule for the simulator and the place agents (issue 42,
// core::StateGate, docs/architecture.md "Plausibility"): a UAV's gateway
// refuses a state further from the last one it accepted than the policy's
// max_step allows, counts it once, and answers it; the recorder and the
// lockstep conductor take the answer without its position; the simulator
// does what the place agents do, with a plugin that flies 5 cells a tick
// while it declares 1.5 (tests/plugins/leaper.cpp).
#include <gtest/gtest.h>

#include <unistd.h>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "pheromesh/core/conductor.hpp"
#include "pheromesh/core/intake.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/run_metrics.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/simulator.hpp"
#include "pheromesh/core/world.hpp"
#include "pheromesh/report/report.hpp"
#include "unit_support.hpp"

namespace pheromesh::core {
namespace state_gate_test {  // named: the unit tests build as one unity source

namespace fs = std::filesystem;
using namespace std::chrono_literals;

using test::state_at;

struct Rules {
  MapGeometry geo{30, 30, 6, 2, 2};
  std::vector<ValueRange> ranges{{0.0F, 1000.0F}};
  IntakeRules rules{geo, 1, ranges, 4};
};

TEST(StateGate, AStateFurtherThanMaxStepIsRefusedOnceAndItsCopiesAreAnsweredUncounted) {
  Rules r;
  StateGate gate;
  const UavStateMsg first = state_at(0, 0, 2, 2);
  const auto a = gate.judge(first, nullptr, {1, 1}, 1.5, 1, r.rules);
  EXPECT_TRUE(a.verdict.taken());
  EXPECT_FALSE(a.refused_motion);
  // 5 cells in one tick: 5 > 1.5 + 1.5.
  const UavStateMsg leap = state_at(0, 1, 7, 2);
  const auto b = gate.judge(leap, &first, {1, 1}, 1.5, 2, r.rules);
  EXPECT_FALSE(b.verdict.taken());
  EXPECT_TRUE(b.refused_motion);
  EXPECT_FALSE(b.copy);
  EXPECT_EQ(b.verdict.refusal, Refusal::ImplausibleState);
  EXPECT_NE(b.verdict.reason.find("further from its last state"), std::string::npos) << b.verdict.reason;
  ASSERT_TRUE(gate.refused_tick(0).has_value());
  EXPECT_EQ(*gate.refused_tick(0), 1U);
  // The same tick again (a re-send, the closing state): answered, not counted.
  const auto c = gate.judge(leap, &first, {1, 1}, 1.5, 2, r.rules);
  EXPECT_TRUE(c.refused_motion);
  EXPECT_TRUE(c.copy);
  // The next tick's leap is a new refusal.
  const auto d = gate.judge(state_at(0, 2, 12, 2), &first, {1, 1}, 1.5, 3, r.rules);
  EXPECT_TRUE(d.refused_motion);
  EXPECT_FALSE(d.copy);
  // Back within reach of the last accepted state: 3 cells in 3 ticks.
  EXPECT_TRUE(gate.judge(state_at(0, 3, 5, 2), &first, {1, 1}, 1.5, 4, r.rules).verdict.taken());
}

TEST(StateGate, ARestartedUavsFirstStatesClearItsEarlierLifesRefusalsButAReSentOldStateDoesNot) {
  Rules r;
  StateGate gate;
  const UavStateMsg last = state_at(0, 50, 10, 10);
  ASSERT_TRUE(gate.judge(state_at(0, 51, 20, 10), &last, {1, 1}, 1.5, 60, r.rules).refused_motion);
  // The same accepted state again (a lockstep re-send): the refusal stands.
  EXPECT_TRUE(gate.judge(last, &last, {1, 1}, 1.5, 60, r.rules).verdict.taken());
  EXPECT_EQ(gate.refused_tick(0), std::optional<uint32_t>(51));
  // A new life from its start cell at tick 0: no refusal of the old one is its answer.
  EXPECT_TRUE(gate.judge(state_at(0, 0, 1, 2), &last, {1, 1}, 1.5, 60, r.rules).verdict.taken());
  EXPECT_FALSE(gate.refused_tick(0).has_value());
}

TEST(StateGate, AMalformedStateIsDroppedNotAnswered) {
  Rules r;
  StateGate gate;
  const auto j = gate.judge(state_at(0, 0, 99, 2), nullptr, {1, 1}, 1.5, 1, r.rules);
  EXPECT_EQ(j.verdict.kind, IntakeVerdict::Kind::Drop);
  EXPECT_FALSE(j.refused_motion) << "only the motion rule's refusal is an answer";
}

TEST(StateGate, TheAnswerIsTheStateMarkedImplausibleWithoutItsUplink) {
  UavStateMsg s = state_at(3, 7, 4, 4);
  s.deposits.resize(2);
  s.deposits_sent = 12;
  const UavStateMsg a = refused_answer(s);
  EXPECT_TRUE(a.implausible);
  EXPECT_TRUE(a.deposits.empty());
  EXPECT_EQ(a.deposits_sent, 12U);
  EXPECT_EQ(a.tick, 7U);
  EXPECT_FALSE(s.implausible) << "the state itself is unchanged";
}

TEST(StateGate, ARefusedStateAnswersTheConductorsUavPhaseButOccupiesNoTile) {
  LockstepConductor::Options o;
  o.uavs = 2;
  o.regions = 2;
  LockstepConductor c(o);
  const auto t0 = LockstepConductor::Clock::time_point{} + 100s;
  (void)c.begin_phase(0, ClockPhase::Uav, t0);
  for (uint32_t u = 0; u < 2; ++u) {
    c.on_phase_done({process_key(kRoleUav, u), 0, static_cast<uint8_t>(ClockPhase::Uav), 0, {}});
  }
  c.on_uav_state(0, 0, {0, 0});
  EXPECT_EQ(c.status(t0).waiting, 1U) << "uav 1's state or its refusal";
  c.on_uav_refused(1, 0);
  EXPECT_TRUE(c.status(t0).complete);
  const ClockMsg place = c.begin_phase(0, ClockPhase::Place, t0);
  ASSERT_EQ(place.states.size(), 2U) << "each gateway holds a state or a refusal's answer";
  // The refused UAV is over no tile in the next announcement: no view waits
  // for it as a neighbour.
  const ClockMsg next = c.begin_phase(1, ClockPhase::Uav, t0);
  ASSERT_EQ(next.occupancy.size(), 1U);
  EXPECT_EQ(next.occupancy[0].count, 1U);
}

TEST(StateGate, TheConductorAnnouncesNoDepositOfARefusedStateToAnyRegion) {
  LockstepConductor::Options o;
  o.uavs = 2;
  o.regions = 2;
  LockstepConductor c(o);
  const auto t0 = LockstepConductor::Clock::time_point{} + 100s;
  (void)c.begin_phase(0, ClockPhase::Uav, t0);
  // Each UAV reports 2 deposits for region 0 and 3 for region 1.
  for (uint32_t u = 0; u < 2; ++u) {
    c.on_phase_done({process_key(kRoleUav, u), 0, static_cast<uint8_t>(ClockPhase::Uav), 0, {{0, 2}, {1, 3}}});
  }
  c.on_uav_state(0, 0, {0, 0});
  c.on_uav_refused(1, 0);  // its gateway rejects the 5 its refused state carried
  ASSERT_TRUE(c.status(t0).complete);
  const ClockMsg place = c.begin_phase(0, ClockPhase::Place, t0);
  ASSERT_EQ(place.deposits.size(), 2U);
  EXPECT_EQ(place.deposits[0].count, 2U) << "uav 0's only";
  EXPECT_EQ(place.deposits[1].count, 3U);
  EXPECT_EQ(c.deposits_lost(), 0U) << "rejected, not lost";
}

ScenarioConfig small_test() {
  auto s = load_scenario(std::string(PHEROMESH_SOURCE_DIR) + "/scenarios/small-test.textproto");
  if (!s) throw std::runtime_error(s.error().message);
  return s.value();
}

TEST(StateGate, TheRecorderTakesARefusedStatesCountersButNotItsPosition) {
  const ScenarioConfig s = small_test();
  const World world(s.geometry(), s.obstacles, s.targets);
  RunRecorder rec(s, world);
  const Cell start = uav_start(s, policy_traits(s), 0);
  UavStateMsg first = state_at(0, 0, start.x, start.y);
  first.deposits_sent = 1;
  ASSERT_TRUE(rec.on_uav_state(first));
  const int64_t covered = rec.coverage().covered_cells();
  UavStateMsg leap = refused_answer(state_at(0, 1, start.x + 9, start.y));
  leap.deposits_sent = 2;
  EXPECT_TRUE(rec.on_uav_state(leap));
  EXPECT_TRUE(rec.on_uav_state(leap)) << "a copy";
  const UavStatus& u = rec.uavs().at(0);
  EXPECT_EQ(u.last.x, first.x) << "its position stays the last accepted one";
  EXPECT_EQ(u.last.deposits_sent, 2U) << "its deposits count";
  EXPECT_EQ(rec.deposits_sent(), 2U);
  EXPECT_EQ(rec.coverage().covered_cells(), covered);
  EXPECT_EQ(rec.refused()[Refusal::ImplausibleState], 0U) << "the gateway counted it, not the ground";
  ASSERT_EQ(rec.states_refused(), 1U) << "once per tick";
  const auto& r = rec.refused_states().at(0);
  EXPECT_EQ(r.first.tick, 1U);
  const RefusedMove m = first_refused_move(r);
  EXPECT_DOUBLE_EQ(m.cells, 9.0);
  EXPECT_EQ(m.ticks, 1U);
  EXPECT_EQ(describe_first_refusal(r, 0, 1.5),
            "uav 0's state of tick 1 refused as implausible: it moved 9 cells in one tick from its last accepted "
            "state (max_step 1.5 allows 3 with the slack of 1.5)");
  EXPECT_EQ(rec.tick_series().at(1).uavs_reporting, 1U) << "its answer counts as reporting at its tick";
}

// The leaper plugin (tests/plugins/leaper.cpp) on small-test's map.
class Leaper : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("phm-leaper-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  ScenarioConfig load(const std::string& config, uint32_t ticks = 40) {
    const std::string path = (dir_ / "leaper.textproto").string();
    std::ofstream(path) << "map { width: 30 height: 30 tile_size: 6 regions_x: 2 regions_y: 2\n"
                        << "  targets { x: 22 y: 8 } }\n"
                        << "swarm { uavs: 4 start_area { x: 1 y: 1 w: 4 h: 4 } }\n"
                        << "run { ticks: " << ticks << " seed: 1 }\n"
                        << "policy { plugin { library: \"" << PHEROMESH_TEST_PLUGIN_DIR
                        << "/libpheromesh_test_plugin_leaper.so\" name: \"leaper\"\n"
                        << config << " } }\n";
    auto s = load_scenario(path);
    if (!s) throw std::runtime_error(s.error().message);
    return s.value();
  }
  fs::path dir_;
};

uint64_t refused_by_places(const RunRecorder& r) { return r.refused_by_places()[Refusal::ImplausibleState]; }

TEST_F(Leaper, ThePolicyThatFliesFiveCellsATickHasItsStatesRefusedByItsGatewayOncePerTick) {
  Simulator sim(load(""));
  sim.run();
  const RunRecorder& r = sim.recorder();
  // Each UAV's first state is 5 cells from its start in one tick (refused);
  // later ones are judged from the last accepted state, or from the start
  // cell in tick + 1 ticks while none was accepted.
  ASSERT_EQ(r.refused_states().size(), 4U);
  EXPECT_GT(r.states_refused(), 4U * 20U);
  EXPECT_LE(r.states_refused(), 4U * 41U) << "at most one per UAV and tick";
  EXPECT_EQ(refused_by_places(r), r.states_refused()) << "the gateways' health counts exactly these";
  EXPECT_EQ(r.refused()[Refusal::ImplausibleState], 0U) << "nobody counts them twice";
  for (const auto& [uav, rs] : r.refused_states()) {
    EXPECT_EQ(rs.first.tick, 0U);
    EXPECT_TRUE(rs.from_start);
    EXPECT_DOUBLE_EQ(first_refused_move(rs).cells, 5.0);
    EXPECT_TRUE(r.uavs().at(uav).finished) << "its closing state (or its answer) says it finished";
  }
  // Every deposit it made is accounted for (the rule judges states only).
  EXPECT_EQ(r.deposits_sent(), 4U * 41U);
  EXPECT_EQ(r.deposits_lost(), 0U);
}

TEST_F(Leaper, ADetourOfOneTickIsRefusedAndTheStateBackOnTheRowAccepted) {
  // One cell a tick along the row; every 10th tick 5 cells off it.
  Simulator sim(load("config { key: \"step\" number: 1 } config { key: \"detour_every\" number: 10 }", 40));
  sim.run();
  const RunRecorder& r = sim.recorder();
  EXPECT_EQ(r.states_refused(), 4U * 4U) << "ticks 10, 20, 30 and 40 of each UAV";
  EXPECT_EQ(refused_by_places(r), 4U * 4U);
  for (const auto& [uav, rs] : r.refused_states()) {
    EXPECT_EQ(rs.first.tick, 10U);
    EXPECT_FALSE(rs.from_start);
    EXPECT_EQ(rs.accepted.tick, 9U);
    EXPECT_EQ(rs.last_tick, 40U);
    // The closing state is tick 40's, refused: the last accepted is tick 39's.
    EXPECT_EQ(r.uavs().at(uav).last.tick, 39U);
  }
}

TEST_F(Leaper, GuardAnHonestLeaperIsRefusedNothing) {
  // The same flight declared honestly (max_step 5): the rule refuses
  // nothing, so the counts above come from the rule, not the plugin.
  Simulator sim(load("config { key: \"max_step\" number: 5 }"));
  sim.run();
  EXPECT_EQ(sim.recorder().states_refused(), 0U);
  EXPECT_EQ(refused_by_places(sim.recorder()), 0U);
}

TEST_F(Leaper, MetricsJsonCarriesTheRefusalsAndTheSummaryNamesTheMove) {
  Simulator sim(load(""));
  sim.run();
  report::RunInfo info;
  info.runner = report::Runner::Simulator;
  info.clock = "lockstep";
  const auto j = report::metrics_json(sim.recorder(), info);
  ASSERT_TRUE(j.contains("states_refused"));
  EXPECT_EQ(j["states_refused"]["total"], sim.recorder().states_refused());
  EXPECT_EQ(j["refused"]["implausible_state"], sim.recorder().states_refused());
  const auto lines = report::refused_state_lines(j);
  ASSERT_EQ(lines.size(), 5U);
  EXPECT_EQ(lines[0].rfind("uav 0's policy moved ", 0), 0U) << lines[0];
  EXPECT_NE(lines[0].find("moved 5 cells in one tick (max_step 1.5): " +
                          std::to_string(sim.recorder().refused_states().at(0).count) +
                          " states refused, the first at tick 0"),
            std::string::npos)
      << lines[0];
  EXPECT_EQ(
      lines[4].rfind(std::to_string(sim.recorder().states_refused()) + " states refused as implausible in all", 0), 0U)
      << lines[4];
  // Nothing refused: no line, no key.
  Simulator honest(load("config { key: \"max_step\" number: 5 }"));
  honest.run();
  const auto h = report::metrics_json(honest.recorder(), info);
  EXPECT_FALSE(h.contains("states_refused"));
  EXPECT_TRUE(report::refused_state_lines(h).empty());
}

TEST_F(Leaper, ValidatesTrialFindsAMaxStepBelowWhatThePolicysMovesNeed) {
  const auto lines = max_step_trial(load(""), 20);
  ASSERT_EQ(lines.size(), 4U) << "one per UAV";
  EXPECT_EQ(lines[0].rfind("uav 0's state of tick 0 refused as implausible: it moved 5 cells in one tick from its "
                           "start cell (max_step 1.5 allows 3 with the slack of 1.5); ",
                           0),
            0U)
      << lines[0];
  EXPECT_NE(lines[0].find(" of its states refused in a trial of 20 ticks"), std::string::npos) << lines[0];
  // Declared honestly, nothing to say.
  EXPECT_TRUE(max_step_trial(load("config { key: \"max_step\" number: 5 }"), 20).empty());
}

TEST(StateGate, TheDepositsOfARefusedStateAreNeitherAppliedNorForwarded) {
  Rules r;
  StateGate gate;
  const UavStateMsg first = state_at(0, 0, 2, 2);
  EXPECT_EQ(carried_deposits(gate.judge(first, nullptr, {1, 1}, 1.5, 1, r.rules)), CarriedDeposits::Judge) << "taken";
  EXPECT_EQ(carried_deposits(gate.judge(state_at(0, 1, 99, 2), &first, {1, 1}, 1.5, 2, r.rules)),
            CarriedDeposits::Judge)
      << "malformed (off the map): dropped, its deposits judged as deposits";
  const auto leap = gate.judge(state_at(0, 1, 9, 2), &first, {1, 1}, 1.5, 2, r.rules);
  EXPECT_EQ(carried_deposits(leap), CarriedDeposits::Reject) << "the UAV's own: rejected by its gateway, counted";
  EXPECT_EQ(carried_deposits(gate.judge(state_at(0, 1, 9, 2), &first, {1, 1}, 1.5, 2, r.rules)),
            CarriedDeposits::Reject)
      << "a copy of it (the rest of the tick's deposits) too";
  const auto stranger = gate.judge(state_at(9, 1, 2, 2), nullptr, {1, 1}, 1.5, 2, r.rules);
  EXPECT_EQ(stranger.verdict.refusal, Refusal::UnknownUav);
  EXPECT_EQ(carried_deposits(stranger), CarriedDeposits::Refuse) << "no UAV's: refused, in no ledger";
  const auto ahead = gate.judge(state_at(0, 50, 2, 2), &first, {1, 1}, 1.5, 2, r.rules);
  EXPECT_EQ(ahead.verdict.refusal, Refusal::TickFarAhead);
  EXPECT_EQ(carried_deposits(ahead), CarriedDeposits::Refuse);
}

TEST(StateGate, ADetectionOlderThanTheKeptPositionsIsRefusedOnlyOnceOlderOnesWereDropped) {
  DetectionMsg d{0, 10, 0, {22, 8}};
  EXPECT_FALSE(check_detection_kept(d, std::nullopt)) << "every position since the UAV's first is kept";
  EXPECT_FALSE(check_detection_kept(d, 10U));
  const auto stale = check_detection_kept(d, 11U);
  ASSERT_TRUE(stale);
  EXPECT_NE(stale->find("older than the oldest of its positions kept (tick 11)"), std::string::npos) << *stale;
}

}  // namespace state_gate_test
}  // namespace pheromesh::core
