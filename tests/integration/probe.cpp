// pheromesh-test-probe: helper process for the integration tests, speaking
// only through the bus (no vendor header here either).
//
//   discover --id I --expect N   announce itself, print "discovered N" once
//                                it sees N participants (itself included),
//                                then stay until SIGTERM (bounded).
//   hostile --region R           send malformed deposits and tiles into a
//                                running swarm; print what it sent, then
//                                stay until SIGTERM (bounded, 60 s): the test
//                                ends it once the swarm counted them.
//   forge --scenario F --uavs N  well-formed but forged samples (issue 16, the
//                                attacks docs/architecture.md "What a receiver
//                                refuses" lists) into a running swarm, once
//                                its lockstep clock passed tick 5 (--lockstep)
//                                or its place agents 0 and 1 are matched, and
//                                the plausible ones of issue 28 (UAV 0's next
//                                deposits, an in-range field chunk), once
//                                every receiver matched the writer it is
//                                written with (and stayed matched 0.5 s in
//                                lockstep, 1.5 s in realtime: the receiver's
//                                side of a match may come later); print
//                                what it sent, then stay
//                                until SIGTERM (bounded, 300 s): the test ends
//                                it once the swarm has exited.
//   idle --id I --regions R      a UAV's endpoints and nothing else, until
//                                SIGTERM: what discovery alone costs
//                                (bench/discovery_idle.sh).
//   hub --cell C --spokes K --first-uav U [--view-writers per-uav|none]
//                                the place agent of cell C, gateway of UAVs
//                                U..U+K-1: the endpoints that match theirs,
//                                no samples; prints "hub C matched K spokes at
//                                EPOCH after S s" once every spoke's view and
//                                command readers matched, then stays until
//                                SIGTERM (bench/discovery_cells.sh).
//   spoke --id U --cell C        `idle`'s UAV endpoints, homed on C; prints
//                                "spoke U matched hub at EPOCH after S s" once
//                                its deposit and state writers matched.
// --cell-index I, --cell-peer [ADDR:]I (repeatable): discovery scoped to a
// cell (bus/cell_discovery.hpp) instead of --dds-profile: a fixed participant
// index (a hub), and the only participants to announce itself to.
// --participant-id I: a Fast DDS member's ports (as pheromesh run gives).
//   snoop --seconds S            read every pheromesh topic for S seconds
//                                (ends early with --until-tiles/--until-clocks)
//                                and try to inject a deposit into region 0;
//                                print what it read and how many readers
//                                matched its writer (DDS Security tests).
//   offend --topic tile|clock    write one tile / one clock sample and stay
//                                --linger seconds; print "refused: ..." if the
//                                bus would not make the writer (permissions).
// --swarm-processes N: how many processes share the host, as `pheromesh run`
// tells its own (above 40 a Cyclone process asks for acknowledgements every
// second: bus/src/dds_profiles.hpp); default --expect for `discover`, else 0
// (not known: Cyclone's 100 ms).
// --secure DIR [--identity NAME]: DDS Security with an identity of DIR
// (default probe-<id>).
// --lease-ms L: the liveliness lease of its manual-by-topic writers (the
// health record of `discover`, which a process asserts ten times per lease
// to every matched reader: bus/src/vendor_pace.hpp). Default 1000 ms, as
// pheromesh processes, but 60000 ms for `discover`: every probe reads every
// other probe's record, N^2 matched pairs that no pheromesh role has, and at
// 1 s those assertions alone were 105 x 104 x 10 = 109,000 datagrams a
// second - more than 2 cores deliver, so 75 Cyclone probes never finished
// discovering each other (docs/dds.md, "One host, 100+ processes").
//
// A watchdog bounds the whole process, whatever DDS call it is blocked in
// (with 100 secured participants, creating or deleting one took minutes and
// nothing in the probe ran meanwhile): `discover` ends by its --timeout,
// counted from the process start, and every subcommand by 2 s after
// SIGINT/SIGTERM; past that the watchdog says so on stderr and ends the
// process (_exit: exit code 1 past --timeout, 5 past a signal's grace).
// --stall S blocks S seconds before the bus is made, deaf to signals and
// deadlines: the integration test's stand-in for such a call.
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/routing.hpp"
#include "pheromesh/bus/typed.hpp"
#include "pheromesh/core/layers.hpp"
#include "pheromesh/core/policy.hpp"
#include "pheromesh/core/scenario.hpp"
#include "pheromesh/core/uav_core.hpp"
#include "pheromesh/runtime/process.hpp"

using namespace pheromesh;
using Clock = std::chrono::steady_clock;

namespace {

// Ends the process from its own thread when the main thread cannot: past
// `deadline` (if any) + the grace, or past the grace after a shutdown
// request. Destroyed (stopped) once the main thread is done with the bus.
class Watchdog {
 public:
  static constexpr std::chrono::seconds kGrace{2};
  // `signal_grace`: how long after SIGINT/SIGTERM the process may take to end.
  Watchdog(std::optional<Clock::time_point> deadline, std::chrono::seconds signal_grace)
      : deadline_(deadline), signal_grace_(signal_grace), thread_([this] { watch(); }) {}
  ~Watchdog() {
    {
      std::lock_guard lock(mu_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

 private:
  void watch() {
    std::optional<Clock::time_point> asked;
    std::unique_lock lock(mu_);
    while (!cv_.wait_for(lock, std::chrono::milliseconds(50), [this] { return stop_; })) {
      const auto now = Clock::now();
      if (!asked && runtime::shutdown_requested()) asked = now;
      if (asked && now > *asked + signal_grace_) {
        char why[96];
        std::snprintf(why, sizeof why, "did not end within %lld s of SIGINT/SIGTERM",
                      static_cast<long long>(signal_grace_.count()));
        die(why, 5);
      }
      if (deadline_ && now > *deadline_ + kGrace) die("did not end within its --timeout (+2 s)", 1);
    }
  }
  [[noreturn]] static void die(const char* why, int code) {
    // write(2), not stdio: the blocked main thread may hold stdout's lock.
    char line[160];
    const int n = std::snprintf(line, sizeof line, "probe watchdog: %s; blocked in a DDS call, exiting\n", why);
    if (n > 0) (void)!::write(STDERR_FILENO, line, static_cast<std::size_t>(std::min(n, 159)));
    ::_exit(code);
  }

  std::optional<Clock::time_point> deadline_;
  std::chrono::seconds signal_grace_;
  std::mutex mu_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::thread thread_;  // last: starts once the members above exist
};

// The deadline runs from `started` (the process start), so that a slow
// participant creation counts against --timeout too.
int discover(bus::Bus& b, uint32_t id, uint32_t expect, Clock::time_point deadline) {
  // Every probe publishes a (transient-local) health record under its own id
  // and counts the distinct ids it receives: one writer and one reader each,
  // so that what is measured is the profile's discovery of participants, not
  // the matching of a ground station's readers (which no probe writes to).
  b.subscribe_health();
  const auto start = Clock::now();
  std::set<uint32_t> seen;
  std::vector<core::HealthMsg> inbox;
  bool reported = false;
  // Published once: TRANSIENT_LOCAL durability delivers it to every reader
  // that matches later.
  b.publish_health({id, 0, 0.0F, 0, 0, 0, 0, false});
  while (!runtime::shutdown_requested() && Clock::now() < deadline) {
    inbox.clear();
    b.take_health(inbox);
    for (const auto& h : inbox) seen.insert(h.region);
    if (!reported && seen.size() >= expect) {
      const double s = std::chrono::duration<double>(Clock::now() - start).count();
      std::printf("discovered %zu in %.2f s\n", seen.size(), s);
      std::fflush(stdout);
      reported = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  // Everyone it heard by the deadline (a cell: only the processes it names).
  std::string heard;
  for (uint32_t i : seen) heard += (heard.empty() ? "" : ",") + std::to_string(i);
  std::printf("heard: %s\n", heard.c_str());
  std::fflush(stdout);
  if (!reported) {
    // Which ids it never heard: the same ids missing at every probe point
    // at those processes, scattered ones at the discovery between pairs.
    std::string missing;
    int listed = 0;
    for (uint32_t i = 0; i < expect && listed < 20; ++i) {
      if (seen.count(i) == 0) {
        missing += (listed++ == 0 ? "" : ", ") + std::to_string(i);
      }
    }
    std::printf("timeout: discovered %zu of %u (not heard: %s)\n", seen.size(), expect, missing.c_str());
    std::fflush(stdout);
    return 1;
  }
  return 0;
}

// Stays (its writers with it) until SIGTERM: 0, or 1 if none came within `bound`.
int stay_until_ended(const char* what, std::chrono::seconds bound) {
  const auto until = Clock::now() + bound;
  while (!runtime::shutdown_requested() && Clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (runtime::shutdown_requested()) return 0;
  std::printf("%s: no SIGTERM within %lld s\n", what, static_cast<long long>(bound.count()));
  return 1;
}

int hostile(bus::Bus& b, uint32_t region, uint32_t map_width) {
  b.offer_deposits(std::vector<core::RegionId>{region});
  const auto deadline = Clock::now() + std::chrono::seconds(20);
  while (b.matched_deposit_readers(region) == 0) {
    if (Clock::now() > deadline || runtime::shutdown_requested()) {
      std::printf("no place agent for region %u\n", region);
      return 1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  // This side's match: the place agent's side of it (and the ground
  // station's of the tile writer) may come later (forge, below).
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const uint32_t uav = 900000;  // not a UAV of the swarm
  int sent = 0;
  auto deposit = [&](uint32_t seq, uint8_t kind, core::Cell c, float amount, core::RegionId r) {
    sent += b.publish_deposit({uav, seq, 1, r, kind, 0, c, amount, {}}, r) ? 1 : 0;
  };
  deposit(1, 0, {1, 1}, std::numeric_limits<float>::quiet_NaN(), region);  // NaN amount
  deposit(2, 0, {static_cast<int32_t>(map_width) + 7, 3}, 1.0F, region);   // cell outside the map
  deposit(3, 9, {1, 1}, 1.0F, region);                                     // unknown kind
  deposit(5, 0, {1, 1}, -std::numeric_limits<float>::infinity(), region);  // negative infinity
  deposit(6, 0, {1, 1}, 1.0F, region);                                     // a valid one ...
  deposit(6, 0, {1, 1}, 1.0F, region);                                     // ... replayed
  // Tiles: declared 2 x 2 but 9 values; a tile outside the map; NaN values.
  // Each on an instance (layer, tx, ty) no place agent writes, so a place
  // agent's next tile cannot replace it in a KEEP_LAST(1) reader before it is
  // read.
  int tiles = 0;
  tiles += b.publish_tile({200, {0, 0}, 1, region, 2, 2, std::vector<float>(9, 1.0F)}) ? 1 : 0;
  tiles += b.publish_tile({0, {4000, 4000}, 1, region, 1, 1, {1.0F}}) ? 1 : 0;
  tiles += b.publish_tile({201, {0, 0}, 1, region, 1, 1, {std::numeric_limits<float>::quiet_NaN()}}) ? 1 : 0;
  // Over the IDL bound: the bus must refuse to write it.
  const bool oversized_written = b.publish_tile({0, {0, 1}, 1, region, 40, 40, std::vector<float>(1600, 0.0F)});
  b.flush(std::chrono::seconds(5));
  std::printf("hostile deposits %d valid 1 tiles %d oversized_written %d refused %llu\n", sent, tiles,
              oversized_written ? 1 : 0, static_cast<unsigned long long>(b.stats().writes_refused));
  std::fflush(stdout);
  // Acknowledged samples are in the readers' caches, but deleting our writers
  // at exit disposes their instances, which can replace a sample the ground
  // station has not taken yet (it polls every 20 ms). The probe cannot see
  // what was taken; the test can (the console's counters), and ends it then.
  return stay_until_ended("hostile", std::chrono::seconds(60));
}

int forge(bus::Bus& b, const std::string& scenario_path, uint32_t uavs, bool lockstep) {
  auto loaded = core::load_scenario(scenario_path);
  if (!loaded) {
    std::printf("%s\n", loaded.error().message.c_str());
    return 2;
  }
  core::ScenarioConfig s = loaded.value();
  if (uavs > 0) s.uavs = uavs;
  const core::MapGeometry geo = s.geometry();
  const uint32_t stranger = 900000;  // no UAV of the swarm
  // States go into the partition of the last region: in a swarm of fewer
  // UAVs than regions no real UAV is homed there, so the forged samples of a
  // real UAV's instance (kept last-1 by a home place agent) cannot push the
  // real ones out; the ground station keeps every state.
  const core::RegionId state_home = geo.region_count() - 1;
  b.join_uav(stranger, state_home);
  // The forged deposits go to region 0 (UAV 0's home) and region 1 (as if
  // region 0 forwarded UAV 0's deposits there).
  const core::RegionId other = geo.region_count() > 1 ? 1 : 0;
  b.offer_deposits(std::vector<core::RegionId>{0, other});
  b.offer_place_exchange(std::vector<core::RegionId>{geo.region_count() > 1 ? 1U : 0U});
  b.subscribe_clock();
  // A plausible state of a real UAV (the last one: homed on a region of its
  // own in a small swarm), into its home's partition: offered now, so that
  // its home has matched it by the time it is written.
  const uint32_t victim = s.uavs - 1;
  const std::string victim_home = bus::routing::home_partition(core::home_region(victim, geo.region_count()));
  bus::Writer<core::UavStateMsg> impostor(b, bus::TopicKind::UavState);
  impostor.offer(victim_home);
  bus::Reader<core::UavStateMsg> states(b, {bus::routing::kAllHomes});
  // Issue 42 D5: a report of UAV 0 into its home's report partition (as if
  // UAV 0 wrote it: its gateway judges it by process).
  const std::string uav0_reports = bus::routing::uav_report_partition(0);
  bus::Writer<core::PhaseDoneMsg> reporter(b, bus::TopicKind::PhaseDone);
  if (lockstep) reporter.offer(uav0_reports);
  // Every other writer a forgery is written with, opened now, and how many
  // readers each must have matched before anything is forged: a sample
  // written before its receiver matched the writer is lost, not refused.
  // The receivers: the ground station (tiles, field chunks, healths; the
  // conductor of lockstep reports), every place agent (served-UAVs chunks,
  // lockstep clocks), one place agent (tiles for views, halo, states,
  // detections). The clocks as relayed to each region's UAVs wait for no
  // match (a region may serve no UAV).
  const core::RegionId to_one = geo.region_count() > 1 ? 1 : 0;
  const uint32_t places = geo.region_count();
  bus::Writer<core::TileMsg> tiles(b);
  bus::Writer<core::FieldMsg> fields(b);
  bus::Writer<core::FieldMsg> place_fields(b, bus::TopicKind::PlaceField);
  bus::Writer<core::HaloMsg> halos(b);
  bus::Writer<core::DetectionMsg> detections(b);
  bus::Writer<core::HealthMsg> healths(b);
  bus::Writer<core::ClockMsg> clocks(b);
  bus::Writer<core::PhaseDoneMsg> reports(b);
  const std::string served_part = bus::routing::kServedPartition,
                    tiles_for_part = bus::routing::tiles_for_partition(to_one),
                    halo_part = bus::routing::halo_partition(0, to_one),
                    detection_part = bus::routing::detection_uplink_partition(state_home);
  struct Match {
    const char* what;
    std::function<uint32_t()> matched;
    uint32_t want;
  };
  const std::vector<Match> matches = [&] {
    std::vector<Match> m{
        {"deposits to region 0", [&] { return b.matched_deposit_readers(0); }, 1},
        {"deposits to region 1", [&] { return b.matched_deposit_readers(other); }, 1},
        {"tiles", [&, p = tiles.offer(bus::routing::tile_partition({0, 0}))] { return b.transport().matched(p); }, 1},
        {"field chunks", [&, p = fields.offer(bus::routing::kFieldPartition)] { return b.transport().matched(p); }, 1},
        // A lockstep place agent reads no served UAVs (the place clock lists them).
        {"served UAVs", [&, p = place_fields.offer(served_part)] { return b.transport().matched(p); },
         lockstep ? 0U : places},
        {"tiles for views", [&, p = place_fields.offer(tiles_for_part)] { return b.transport().matched(p); }, 1},
        {"halo", [&, p = halos.offer(halo_part)] { return b.transport().matched(p); }, 1},
        {"states", [&] { return b.matched_state_readers(); }, 1},
        {"detections", [&, p = detections.offer(detection_part)] { return b.transport().matched(p); }, 1},
        {"healths", [&, p = healths.offer(bus::routing::kGroundPartition)] { return b.transport().matched(p); }, 1},
        {"impostor state", [&] { return impostor.matched(victim_home); }, 1}};
    if (lockstep) {
      m.push_back({"clocks", [&, p = clocks.offer(bus::routing::kClockPartition)] { return b.transport().matched(p); },
                   places});
      m.push_back(
          {"reports", [&, p = reports.offer(bus::routing::kClockPartition)] { return b.transport().matched(p); }, 1});
      m.push_back({"UAV 0's reports", [&] { return reporter.matched(uav0_reports); }, 1});
    }
    return m;
  }();
  // The first writer still short of its receivers ("" once all matched).
  const auto unmatched = [&]() -> std::string {
    for (const auto& m : matches) {
      if (const uint32_t n = m.matched(); n < m.want) {
        return std::string(m.what) + " (" + std::to_string(n) + " of " + std::to_string(m.want) + " readers)";
      }
    }
    return "";
  };
  // UAV 0's latest state (the forged detection is of its tick and far from
  // it) and the victim's (for the plausible forgery), taken while waiting:
  // a lockstep run is over in seconds.
  std::optional<core::UavStateMsg> uav0, last_of_victim;
  uint32_t uav0_seq = 0;  // the highest deposit seq UAV 0's states carried
  std::vector<core::UavStateMsg> got;
  const auto take_states = [&] {
    got.clear();
    states.take(got);
    for (const auto& st : got) {
      for (const auto& d : st.deposits) {
        if (st.uav == 0) uav0_seq = std::max(uav0_seq, d.seq);
      }
      if (st.uav == 0 && (!uav0 || st.tick > uav0->tick)) uav0 = st;
      if (st.uav == victim && (!last_of_victim || st.tick > last_of_victim->tick)) last_of_victim = st;
    }
    return uav0 && uav0->tick > 0 && last_of_victim && last_of_victim->tick > 0;
  };
  // Wait until the swarm runs: every receiver has latched its conductor.
  // A match seen here is this side's: the receiver matches the forger's
  // writer when the forger's announcement of it reaches the receiver, which
  // may come later (a mixed realtime run once lost the 1e30 and far-ahead
  // chunks and the halo that way: written to a reader that did not yet
  // know their writer). So every writer stays matched for `settle` first.
  uint32_t tick = 1;
  const auto deadline = Clock::now() + std::chrono::seconds(90);
  const auto settle = std::chrono::milliseconds(lockstep ? 500 : 1500);
  std::optional<Clock::time_point> all_matched;
  const auto settled = [&] {
    if (!unmatched().empty()) {
      all_matched.reset();
      return false;
    }
    if (!all_matched) all_matched = Clock::now();
    return Clock::now() - *all_matched >= settle;
  };
  std::vector<core::ClockMsg> clock;
  std::optional<Clock::time_point> at_tick5;
  for (;;) {
    const bool heard = take_states();
    if (Clock::now() > deadline || runtime::shutdown_requested()) {
      std::printf("the swarm did not start\n");
      return 1;
    }
    if (lockstep) {
      clock.clear();
      b.take_clock(clock);
      for (const auto& c : clock) tick = std::max(tick, c.tick);
      // From tick 5, up to 3 s more (a run is over in seconds) until every
      // receiver matched its writer and UAV 0's and the victim's states
      // came (stop 39's flake: forged samples written before a match).
      if (tick >= 5 && !at_tick5) at_tick5 = Clock::now();
      const bool ready = settled();
      if (at_tick5 && ready && heard) break;
      if (at_tick5 && Clock::now() - *at_tick5 > std::chrono::seconds(3)) {
        const std::string short_of = unmatched();
        std::printf("forging although not %s: %s\n", short_of.empty() ? "settled" : "matched", short_of.c_str());
        break;
      }
    } else if (settled()) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  // Lockstep forges now, at UAV 0's latest tick. Without a state of the
  // victim, its impostor state is the victim at its start cell at the
  // clock's tick, refused for its writer before anything else is looked at.
  // Realtime waits for the victim's latest state and forges one it could
  // fly to.
  if (lockstep) {
    if (uav0) tick = uav0->tick;
    if (!last_of_victim) {
      const core::Cell start = core::uav_start(s, core::policy_traits(s), victim);
      core::UavStateMsg at_start;
      at_start.uav = victim;
      at_start.tick = tick;
      at_start.x = start.x;
      at_start.y = start.y;
      at_start.view = start;
      last_of_victim = at_start;
    }
  } else {
    const auto until = Clock::now() + std::chrono::seconds(10);
    while (!take_states() && Clock::now() < until && !runtime::shutdown_requested()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (uav0) tick = std::max(tick, uav0->tick);
  }
  if (!last_of_victim) {
    std::printf("heard no state of uav %u\n", victim);
    return 1;
  }
  const uint32_t far_tick = 1U << 31U;
  constexpr float kHuge = 1e30F;
  int sent = 0;
  const auto count = [&](bool ok) { sent += ok ? 1 : 0; };
  const core::Rect r0 = geo.region_rect(0);
  // Deposits: a phantom target mark from a UAV that does not exist; the
  // sequence number 2^32-1 under UAV 0's id (homed on region 0), forwarded
  // as if by region 0 to region 1; and (issue 28) the next 10 sequence
  // numbers UAV 0 will use, plausible in every field, into its home.
  core::DepositMsg mark{
      stranger, 1, tick + 1, 0, static_cast<uint8_t>(core::DepositKind::TargetMark), 0, {r0.x0 + 1, r0.y0 + 1},
      1.0F,     {}};
  count(b.publish_deposit(mark, 0));
  const core::Rect r1 = geo.region_rect(other);
  core::DepositMsg latch{0,
                         std::numeric_limits<uint32_t>::max(),
                         tick + 1,
                         other,
                         static_cast<uint8_t>(core::DepositKind::PathVisit),
                         0,
                         {r1.x0 + 1, r1.y0 + 1},
                         1.0F,
                         {}};
  count(b.publish_deposit(latch, other));
  bool next_written = true;
  for (uint32_t k = 1; k <= 10; ++k) {
    const core::DepositMsg next{
        0, uav0_seq + k,           tick + 1, 0, static_cast<uint8_t>(core::DepositKind::PathVisit),
        0, {r0.x0 + 2, r0.y0 + 2}, 1.0F,     {}};
    next_written = b.publish_deposit(next, 0) && next_written;
  }
  count(next_written);
  // Tiles to the ground station: 1e30 values, and a tick far ahead.
  const core::Rect t00 = geo.tile_rect({0, 0});
  const auto cells = static_cast<std::size_t>(t00.area());
  const auto w = static_cast<uint16_t>(t00.w), h = static_cast<uint16_t>(t00.h);
  count(tiles.write({0, {0, 0}, tick, 0, w, h, std::vector<float>(cells, kHuge)}));
  count(tiles.write({1, {0, 0}, far_tick, 0, w, h, std::vector<float>(cells, 0.5F)}));
  // Field chunks of region 0 (on chunk instances its place agent does not
  // write): 1e30 values, and a tick far ahead.
  core::TileMsg patch{0, {0, 0}, tick, 0, w, h, std::vector<float>(cells, kHuge)};
  count(fields.write({0, 5, 6, tick, {patch}, {}, 0}, bus::routing::kFieldPartition));
  // The same 1e30 tile as region 0's tiles for region 1's views, and a
  // served-UAVs chunk of region 0 naming a UAV that does not exist (what the
  // place agents exchange among themselves).
  count(place_fields.write({0, 5, 6, tick, {patch}, {}, 0}, tiles_for_part));
  core::UavStateMsg ghost;
  ghost.uav = stranger;
  ghost.tick = tick;
  count(place_fields.write({0, 5, 6, tick, {}, {ghost}, 0}, served_part));
  patch.values.assign(cells, 0.5F);
  // Plausible (issue 28): region 0's tile (0,0) in range, of the next tick.
  patch.tick = tick + 1;
  count(fields.write({0, 3, 6, tick + 1, {patch}, {}, 0}, bus::routing::kFieldPartition));
  patch.tick = far_tick;
  count(fields.write({0, 4, 6, far_tick, {patch}, {}, 0}, bus::routing::kFieldPartition));
  // The same tile in range but far ahead, for region 1's views.
  count(place_fields.write({0, 4, 6, far_tick, {patch}, {}, 0}, tiles_for_part));
  // Region 0's border ring as its neighbour region 1 reads it, with 1e30, for
  // the next place phase.
  const std::size_t ring = core::ring_indices_facing(geo, r0, geo.region_rect(to_one)).size();
  count(halos.write({0, tick + 1, std::vector<float>(ring, kHuge), std::vector<float>(ring, 0.0F)}, halo_part));
  // States: UAV 0 across the map, a UAV that does not exist, UAV 1 far ahead in time.
  core::UavStateMsg st;
  st.uav = 0;
  st.tick = tick;
  st.x = geo.width() - 2;
  st.y = geo.height() - 2;
  st.view = {geo.width() - 2, geo.height() - 2};
  count(b.publish_uav_state(st));
  st.uav = stranger;
  // Issue 42 D4: the stranger's state carries three plausible deposits of
  // UAV 0 (its next sequence numbers, in region 0 near its latest state):
  // refused with the state by the place agent it reaches, never forwarded
  // to region 0 in a real place agent's name.
  for (uint32_t k = 21; k <= 23; ++k) {
    const core::Cell c = uav0 ? core::state_cell(*uav0) : core::Cell{r0.x0 + 1, r0.y0 + 1};
    st.deposits.push_back(
        {0, uav0_seq + k, tick, geo.region_of(c), static_cast<uint8_t>(core::DepositKind::PathVisit), 0, c, 1.0F, {}});
  }
  count(b.publish_uav_state(st));
  st.deposits.clear();
  st.uav = s.uavs > 1 ? 1 : 0;
  st.tick = far_tick;
  count(b.publish_uav_state(st));
  // Detections: UAV 0 reports a target far from it (the farthest from its
  // latest state, or the last one without a state); a UAV that does not
  // exist reports one.
  if (!s.targets.empty()) {
    auto far = static_cast<int32_t>(s.targets.size() - 1);
    if (uav0) {
      const auto d2 = [&](const core::Cell& c) {
        const double dx = c.x - uav0->x, dy = c.y - uav0->y;
        return dx * dx + dy * dy;
      };
      for (int32_t k = 0; k < static_cast<int32_t>(s.targets.size()); ++k) {
        if (d2(s.targets[static_cast<std::size_t>(k)]) > d2(s.targets[static_cast<std::size_t>(far)])) far = k;
      }
    }
    const core::Cell target = s.targets[static_cast<std::size_t>(far)];
    count(detections.write({0, tick, far, target}, detection_part));
    count(detections.write({stranger, tick, far, target}, detection_part));
  }
  // Issue 42 D5. Healths of place agents the run does not have (a standby
  // of region 0 in a swarm without standbys, a region beyond the map's),
  // with counters that would replace region 0's: refused at the ground
  // station, and this process stays no place agent for any relay.
  core::HealthMsg fake{0, tick, 0.0F, 5, 1, 0, 0, false};
  fake.replica = 1;
  count(healths.write(fake, bus::routing::kGroundPartition));
  fake.replica = 0;
  fake.region = geo.region_count();
  count(healths.write(fake, bus::routing::kGroundPartition));
  // A served-UAVs chunk naming UAV 0 where it is: as region 0's own replica
  // (another process holds it) and as a standby it does not have.
  if (uav0) {
    core::UavStateMsg where = *uav0;
    where.deposits.clear();
    count(place_fields.write({0, 4, 6, tick, {}, {where}, 0}, served_part));
    count(place_fields.write({0, 3, 6, tick, {}, {where}, 1}, served_part));
  }
  // Lockstep: a forwarded deposit of UAV 0 of the tick before, to region 1
  // (its backup, not its gateway): no UAV announced it for any place phase
  // to come; applied, it would land a tick late. Realtime: from a process
  // that is no place agent's.
  const core::Cell late_cell{r1.x0 + 1, r1.y0 + 1};
  count(b.publish_deposit({0,
                           uav0_seq + 30,
                           tick > 0 ? tick - 1 : 0,
                           other,
                           static_cast<uint8_t>(core::DepositKind::PathVisit),
                           0,
                           late_cell,
                           1.0F,
                           {}},
                          other));
  // Lockstep reports (PhaseDone) of the next UAV phase, claiming deposits:
  // of UAV 0 and of place agent 0 straight to the conductor, and of UAV 0
  // into its home's report partition. A forged one taken would finish a
  // phase for a process that has not, or announce deposits never made.
  if (lockstep) {
    core::PhaseDoneMsg done{
        core::process_key(core::kRoleUav, 0), tick + 1, static_cast<uint8_t>(core::ClockPhase::Uav), 0, {{0, 5}}};
    count(reports.write(done, bus::routing::kClockPartition));
    count(reporter.write(done, uav0_reports));
    done.process = core::process_key(core::kRolePlace, core::place_id(0, 0));
    done.phase = static_cast<uint8_t>(core::ClockPhase::Place);
    done.deposits.clear();
    count(reports.write(done, bus::routing::kClockPartition));
  }
  // A clock that stops the run, from this process's own writer: to the place
  // agents, and as if relayed to every region's UAVs (the lockstep tree).
  core::ClockMsg stop;
  stop.tick = tick;
  stop.phase = static_cast<uint8_t>(core::ClockPhase::Stop);
  count(clocks.write(stop, bus::routing::kClockPartition));
  for (core::RegionId r = 0; r < geo.region_count(); ++r) count(b.relay_clock(stop, r));
  // Last (it waits for a match; the detections above must go out at their
  // tick): the victim one cell from where it was, a tick later - a state it
  // could fly to (issue 28) - from a writer that is not its own. Its home
  // reads the latest state of each UAV only (keep-last 1): the UAV's own
  // next state may replace a forged one before the home takes it, so it is
  // written several times, 15 ms apart (counted once).
  core::UavStateMsg twin = *last_of_victim;
  twin.x = std::min(twin.x + 1.0, static_cast<double>(geo.width() - 1));
  // Matched first: a home that matched the impostor late would get only its
  // last state (transient-local, keep-last 1), likelier replaced unseen.
  const auto matched_by = Clock::now() + std::chrono::seconds(5);
  while (impostor.matched(victim_home) == 0 && Clock::now() < matched_by && !runtime::shutdown_requested()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  bool twin_written = true;
  for (uint32_t k = 1; k <= 8; ++k) {
    twin.tick = last_of_victim->tick + k;
    twin_written = impostor.write(twin, victim_home) && twin_written;
    std::this_thread::sleep_for(std::chrono::milliseconds(15));
  }
  count(twin_written);
  b.flush(std::chrono::seconds(5));
  std::printf("forged %d samples at tick %u\n", sent, tick);
  std::fflush(stdout);
  // Our writers stay until the test ends us, after the swarm has exited:
  // deleting them would dispose their instances, which can replace a sample
  // a receiver has not taken yet (see hostile).
  return stay_until_ended("forge", std::chrono::seconds(300));
}

// Exactly the endpoints a realtime UAV creates (UavApp::run), homed on
// `home`; then takes what arrives until SIGTERM, calling `each` after every
// wait (idle and spoke).
template <typename Each>
void as_idle_uav(bus::Bus& b, uint32_t id, core::RegionId home, Each each) {
  b.join_uav(id, home);
  b.subscribe_broadcasts();
  b.subscribe_commands();
  std::vector<core::ViewMsg> views;
  std::vector<core::CommandMsg> commands;
  while (!runtime::shutdown_requested()) {
    b.wait({bus::TopicKind::View, bus::TopicKind::Command}, Clock::now() + std::chrono::milliseconds(200));
    views.clear();
    commands.clear();
    b.take_views(views);
    b.take_commands(commands);
    each();
  }
}

int idle(bus::Bus& b, uint32_t id, uint32_t regions) {
  as_idle_uav(b, id, core::home_region(id, regions), [] {});
  return 0;
}

double epoch_s() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The endpoints a gateway place agent holds for its UAVs: every writer and
// reader that matches one of a UAV's (idle above), so that the hub discovers
// exactly what a cell's place agent will.
// `view_writers` false: no view writer at all (an experiment: a writer per
// UAV makes every spoke learn all K of its hub's view writers, K^2 endpoint
// announcements per cell); then the command writer's matches alone count.
int hub(bus::Bus& b, uint32_t cell, uint32_t spokes, uint32_t first_uav, bool view_writers, Clock::time_point started) {
  b.subscribe_deposits(cell);
  b.subscribe_home_states(cell);
  std::vector<uint32_t> uavs(spokes);
  for (uint32_t k = 0; k < spokes; ++k) uavs[k] = first_uav + k;
  bus::Reader<core::DetectionMsg> detections(b, {bus::routing::kGroundPartition});
  bus::Writer<core::CommandMsg> commands(b);
  commands.offer(bus::routing::kCommandPartition);
  bus::Writer<core::BroadcastMsg> broadcasts(b);
  broadcasts.offer(bus::routing::kBroadcastPartition);
  // A view writer per UAV (Bus::offer_views's), held here so that its
  // matches say which spokes are there.
  bus::Writer<core::ViewMsg> views(b);
  if (view_writers) {
    for (uint32_t u : uavs) views.offer(bus::routing::view_partition(u));
  }
  bool reported = false;
  auto last_progress = Clock::now();
  std::vector<core::DepositMsg> deposits;
  std::vector<core::UavStateMsg> states;
  std::vector<core::DetectionMsg> seen;
  while (!runtime::shutdown_requested()) {
    b.wait({bus::TopicKind::Deposit}, Clock::now() + std::chrono::milliseconds(200));
    deposits.clear();
    states.clear();
    seen.clear();
    b.take_deposits(deposits);
    b.take_uav_states(states);
    detections.take(seen);
    if (reported) continue;
    uint32_t matched = 0;
    for (uint32_t u : uavs) matched += !view_writers || views.matched(bus::routing::view_partition(u)) > 0 ? 1 : 0;
    const uint32_t command_readers = commands.matched(bus::routing::kCommandPartition);
    if (matched == spokes && command_readers >= spokes) {
      std::printf("hub %u matched %u spokes at %.3f after %.2f s\n", cell, spokes, epoch_s(), seconds_since(started));
      std::fflush(stdout);
      reported = true;
    } else if (Clock::now() - last_progress > std::chrono::seconds(10)) {
      std::printf("hub %u: %u of %u spokes' views, %u command readers after %.0f s\n", cell, matched, spokes,
                  command_readers, seconds_since(started));
      std::fflush(stdout);
      last_progress = Clock::now();
    }
  }
  return reported ? 0 : 1;
}

int spoke(bus::Bus& b, uint32_t id, uint32_t cell, Clock::time_point started) {
  // Exactly idle's endpoints, homed on the cell's place agent.
  bool reported = false;
  as_idle_uav(b, id, cell, [&] {
    if (!reported && b.matched_state_readers() > 0) {
      std::printf("spoke %u matched hub at %.3f after %.2f s\n", id, epoch_s(), seconds_since(started));
      std::fflush(stdout);
      reported = true;
    }
  });
  return reported ? 0 : 1;
}

// "[ADDR:]INDEX", the address 127.0.0.1 when left out.
std::optional<bus::CellPeer> parse_cell_peer(const std::string& text) {
  const std::size_t colon = text.rfind(':');
  bus::CellPeer p{colon == std::string::npos ? "127.0.0.1" : text.substr(0, colon), 0};
  const std::string index = colon == std::string::npos ? text : text.substr(colon + 1);
  char* end = nullptr;
  const unsigned long v = std::strtoul(index.c_str(), &end, 10);
  if (index.empty() || *end != '\0' || v > 100000) return std::nullopt;
  p.index = static_cast<uint32_t>(v);
  return p;
}

int snoop(bus::Bus& b, double seconds, uint64_t until_tiles, uint64_t until_clocks) {
  b.subscribe_ground();
  b.subscribe_broadcasts();
  b.subscribe_scenario();
  b.subscribe_commands();
  b.subscribe_clock();
  b.subscribe_phase_done();
  std::vector<core::TileMsg> tiles;
  std::vector<core::FieldMsg> fields;
  std::vector<core::UavStateMsg> states;
  std::vector<core::DetectionMsg> detections;
  std::vector<core::TargetEventMsg> events;
  std::vector<core::HealthMsg> health;
  std::vector<core::BroadcastMsg> broadcasts;
  std::vector<core::ScenarioMsg> scenarios;
  std::vector<core::CommandMsg> commands;
  std::vector<core::ClockMsg> clocks;
  std::vector<core::PhaseDoneMsg> dones;
  const auto deadline = Clock::now() + std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000));
  uint32_t injected = 0, most_matched = 0;
  // A deposit into region 0 from a UAV the swarm does not have, every 200 ms:
  // a place agent that accepted it would count it as rejected (unknown UAV's
  // sequence) or applied, and the run's accounting would show it.
  // A secure identity without the right (the monitor) cannot even make the
  // writer: then it only reads.
  uint32_t seq = 0;
  bool can_write = true;
  while (!runtime::shutdown_requested() && Clock::now() < deadline) {
    if (can_write) {
      try {
        b.offer_deposits(std::vector<core::RegionId>{0});
        most_matched = std::max(most_matched, b.matched_deposit_readers(0));
        injected += b.publish_deposit({900001, ++seq, 1, 0, 0, 0, {1, 1}, 1.0F, {}}, 0) ? 1 : 0;
      } catch (const std::exception& e) {
        std::printf("deposit writer refused: %s\n", e.what());
        can_write = false;
      }
    }
    b.take_tiles(tiles);
    b.take_fields(fields);
    b.take_uav_states(states);
    b.take_detections(detections);
    b.take_target_events(events);
    b.take_health(health);
    b.take_broadcasts(broadcasts);
    b.take_scenarios(scenarios);
    b.take_commands(commands);
    b.take_clock(clocks);
    b.take_phase_done(dones);
    if ((until_tiles > 0 || until_clocks > 0) && tiles.size() >= until_tiles && clocks.size() >= until_clocks) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  const std::size_t total = tiles.size() + fields.size() + states.size() + detections.size() + events.size() +
                            health.size() + broadcasts.size() + scenarios.size() + commands.size() + clocks.size() +
                            dones.size();
  std::printf(
      "snooped %zu samples: tiles %zu fields %zu states %zu detections %zu events %zu health %zu broadcasts %zu "
      "scenarios %zu commands %zu clocks %zu phase_done %zu; deposits written %u, most readers matched %u\n",
      total, tiles.size(), fields.size(), states.size(), detections.size(), events.size(), health.size(),
      broadcasts.size(), scenarios.size(), commands.size(), clocks.size(), dones.size(), injected, most_matched);
  std::fflush(stdout);
  return 0;
}

int offend(bus::Bus& b, const std::string& what, double linger_s) {
  bool written = false;
  try {
    if (what == "tile") {
      written = b.publish_tile({0, {0, 0}, 7, 0, 1, 1, {42.0F}});
    } else if (what == "clock") {
      written = b.publish_clock({7, 0, 0, {}, {}, {}, {}});
    } else {
      std::fprintf(stderr, "unknown --topic %s\n", what.c_str());
      return 2;
    }
  } catch (const std::exception& e) {
    std::printf("refused: %s\n", e.what());
    std::fflush(stdout);
    return 0;
  }
  std::printf("%s %s\n", what.c_str(), written ? "written" : "not written");
  std::fflush(stdout);
  // Transient-local: a reader that matches while this writer lives gets it.
  const auto until = Clock::now() + std::chrono::milliseconds(static_cast<int64_t>(linger_s * 1000));
  while (!runtime::shutdown_requested() && Clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pheromesh integration-test probe", "pheromesh-test-probe"};
  app.require_subcommand(1);
  std::string dds = bus::default_vendor(), profile = "onehost";
  uint32_t domain = 0;
  app.add_option("--dds", dds);
  app.add_option("--dds-profile", profile);
  app.add_option("--domain", domain);
  uint32_t id = 0, expect = 0, region = 0, width = 30;
  double timeout_s = 120;
  auto* d = app.add_subcommand("discover", "announce and count participants");
  d->add_option("--id", id)->required();
  d->add_option("--expect", expect)->required();
  d->add_option("--timeout", timeout_s, "[s] from the process start")->check(CLI::Range(0.001, 86400.0));
  uint32_t regions = 16;
  auto* i = app.add_subcommand("idle", "a UAV's endpoints, no samples, until SIGTERM");
  i->add_option("--id", id)->required();
  i->add_option("--regions", regions);
  auto* h = app.add_subcommand("hostile", "send malformed samples");
  h->add_option("--region", region);
  h->add_option("--map-width", width);
  double seconds = 10, linger_s = 10;
  uint64_t until_tiles = 0, until_clocks = 0;
  auto* sn = app.add_subcommand("snoop", "read every topic, try to inject deposits");
  sn->add_option("--seconds", seconds);
  sn->add_option("--until-tiles", until_tiles);
  sn->add_option("--until-clocks", until_clocks);
  std::string what;
  auto* of = app.add_subcommand("offend", "write a tile or a clock sample");
  of->add_option("--topic", what)->required();
  of->add_option("--linger", linger_s);
  uint32_t cell = 0, spokes = 0, first_uav = 0;
  auto* hb = app.add_subcommand("hub", "a cell's place agent: the endpoints matching its UAVs', no samples");
  hb->add_option("--cell", cell)->required();
  hb->add_option("--spokes", spokes)->required();
  hb->add_option("--first-uav", first_uav)->required();
  std::string view_writers = "per-uav";
  hb->add_option("--view-writers", view_writers, "per-uav (a place agent's), or none (an experiment)")
      ->check(CLI::IsMember({"per-uav", "none"}));
  auto* sp = app.add_subcommand("spoke", "a UAV's endpoints homed on --cell, no samples");
  sp->add_option("--id", id)->required();
  sp->add_option("--cell", cell)->required();
  int32_t cell_index = -1, participant_id = -1;
  std::vector<std::string> cell_peers;
  app.add_option("--cell-index", cell_index);
  app.add_option("--cell-peer", cell_peers);
  app.add_option("--participant-id", participant_id);
  double stall_s = 0;
  app.add_option("--stall", stall_s,
                 "[s] block this long before making the bus, deaf to signals (test of the watchdog)")
      ->check(CLI::Range(0.0, 3600.0));
  int64_t signal_grace_s = 2;
  app.add_option("--grace", signal_grace_s, "[s] after SIGINT/SIGTERM the watchdog ends the process past this (exit 5)")
      ->check(CLI::Range(int64_t{1}, int64_t{600}));
  int64_t swarm_processes = -1;
  app.add_option("--swarm-processes", swarm_processes,
                 "processes on the host, as pheromesh run tells its own (sizes Cyclone's heartbeat; "
                 "default: --expect for discover, else 0, not known)")
      ->check(CLI::Range(int64_t{0}, int64_t{1000000}));
  int64_t lease_ms = 0;
  app.add_option("--lease-ms", lease_ms,
                 "[ms] liveliness lease of its writers (default: 60000 for discover, else 1000)")
      ->check(CLI::Range(int64_t{1}, int64_t{3600000}));
  std::string secure, identity;
  app.add_option("--secure", secure);
  app.add_option("--identity", identity);
  std::string scenario;
  uint32_t uavs = 0;
  bool lockstep = false;
  auto* f = app.add_subcommand("forge", "send well-formed forged samples");
  f->add_option("--scenario", scenario)->required();
  f->add_option("--uavs", uavs);
  f->add_flag("--lockstep", lockstep);
  CLI11_PARSE(app, argc, argv);
  const auto started = Clock::now();
  spdlog::set_level(spdlog::level::warn);
  runtime::install_shutdown_handlers();
  const auto deadline = started + std::chrono::milliseconds(static_cast<int64_t>(timeout_s * 1000));
  // Declared before the bus: it watches the bus's destruction too.
  Watchdog watchdog(d->parsed() ? std::optional(deadline) : std::nullopt, std::chrono::seconds(signal_grace_s));
  // sleep_for resumes after a signal (libstdc++ sleeps again for the rest).
  // The line says the watchdog and the handlers are in place (a test waits for it).
  if (stall_s > 0) {
    std::fprintf(stderr, "probe: stalling for %.1f s\n", stall_s);
    std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int64_t>(stall_s * 1000)));
  }
  bus::BusOptions o;
  o.process_name = "probe";
  o.domain = domain;
  o.profile = profile;
  o.secure_dir = secure;
  o.identity = identity.empty() ? "probe-" + std::to_string(id) : identity;
  o.participant_id = participant_id;
  if (lease_ms > 0) {
    o.liveliness_lease = std::chrono::milliseconds(lease_ms);
  } else if (d->parsed()) {
    o.liveliness_lease = std::chrono::minutes(1);
  }
  // As `pheromesh run` tells its processes: how many share the host.
  if (swarm_processes >= 0) {
    o.swarm_processes = static_cast<uint32_t>(swarm_processes);
  } else if (d->parsed()) {
    o.swarm_processes = expect;
  }
  if (cell_index >= 0 || !cell_peers.empty()) {
    bus::CellDiscovery c;
    c.domain = domain;
    if (cell_index >= 0) c.index = static_cast<uint32_t>(cell_index);
    for (const auto& text : cell_peers) {
      auto p = parse_cell_peer(text);
      if (!p) {
        std::fprintf(stderr, "--cell-peer '%s': expected [ADDR:]INDEX\n", text.c_str());
        return 2;
      }
      c.peers.push_back(*p);
    }
    auto checked = bus::check_cell(c);
    if (!checked) {
      std::fprintf(stderr, "%s\n", checked.error().message.c_str());
      return 2;
    }
    o.cell = std::move(checked).value();
  }
  // Under PHEROMESH_DDS=mixed the probes alternate vendors by id.
  if (dds == "mixed") dds = id % 2 == 0 ? "cyclone" : "fastdds";
  auto b = bus::make_bus(dds, o);
  if (!b) {
    std::fprintf(stderr, "%s\n", b.error().message.c_str());
    return 3;
  }
  if (d->parsed()) return discover(*b.value(), id, expect, deadline);
  if (i->parsed()) return idle(*b.value(), id, regions);
  if (hb->parsed()) return hub(*b.value(), cell, spokes, first_uav, view_writers == "per-uav", started);
  if (sp->parsed()) return spoke(*b.value(), id, cell, started);
  if (sn->parsed()) return snoop(*b.value(), seconds, until_tiles, until_clocks);
  if (of->parsed()) return offend(*b.value(), what, linger_s);
  if (f->parsed()) return forge(*b.value(), scenario, uavs, lockstep);
  return hostile(*b.value(), region, width);
}
