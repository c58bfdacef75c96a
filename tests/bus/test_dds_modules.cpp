// The DDS modules (common/bus/src/vendors.hpp): where a program finds its
// vendor's module, what it refuses, and a module's bus talking to a bus
// linked in, both ways, on loopback, domain 60 (which no integration test
// uses). The programs load their vendor this way in every integration test.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "pheromesh/bus/bus.hpp"
#include "vendors.hpp"

using namespace pheromesh;  // NOLINT
using Clock = std::chrono::steady_clock;

namespace {

bus::BusOptions options(const std::string& name) {
  bus::BusOptions o;
  o.process_name = name;
  o.domain = 60;
  return o;
}

}  // namespace

TEST(DdsModules, AProgramFindsItsModuleInTheFolderBesideItsOwnOrWhereTheEnvironmentSays) {
  EXPECT_EQ(bus::module_path("cyclone", std::nullopt, "/opt/pheromesh/bin", "../lib/pheromesh"),
            "/opt/pheromesh/lib/pheromesh/libpheromesh_dds_cyclone.so");
  EXPECT_EQ(bus::module_path("fastdds", std::nullopt, "/usr/bin", "../lib/x86_64-linux-gnu/pheromesh"),
            "/usr/lib/x86_64-linux-gnu/pheromesh/libpheromesh_dds_fastdds.so");
  EXPECT_EQ(bus::module_path("fastdds", std::string("/srv/dds"), "/usr/bin", "../lib/pheromesh"),
            "/srv/dds/libpheromesh_dds_fastdds.so");
  EXPECT_EQ(bus::module_path("cyclone", std::string(), "/usr/bin", "../lib/pheromesh"),
            "/usr/lib/pheromesh/libpheromesh_dds_cyclone.so")
      << "an empty variable is as if unset";
}

TEST(DdsModules, AModuleOfAnotherBuildOrVendorIsRefusedNamingWhy) {
  bus::TransportModule good{.vendor = "cyclone", .make = [](const bus::BusOptions&) {
                              return core::Result<std::unique_ptr<bus::Transport>>(core::Error{"unused"});
                            }};
  EXPECT_FALSE(bus::module_mismatch(&good, "cyclone", "/m.so"));
  EXPECT_NE(bus::module_mismatch(nullptr, "cyclone", "/m.so")->find("/m.so returned no entry"), std::string::npos);
  auto old = good;
  old.abi = bus::kTransportModuleAbi + 1;
  EXPECT_NE(bus::module_mismatch(&old, "cyclone", "/m.so")->find("built for another pheromesh"), std::string::npos);
  auto bigger = good;
  bigger.options_size = sizeof(bus::BusOptions) + 8;
  EXPECT_NE(
      bus::module_mismatch(&bigger, "cyclone", "/m.so")->find("options of " + std::to_string(bigger.options_size)),
      std::string::npos);
  EXPECT_NE(bus::module_mismatch(&good, "fastdds", "/m.so")->find("is not the 'fastdds' bus (it says 'cyclone')"),
            std::string::npos);
}

TEST(DdsModules, AMissingModuleOrAModuleOfTheOtherVendorIsAnErrorNotACrash) {
  const auto missing = bus::load_transport_module("cyclone", "/nonexistent/libpheromesh_dds_cyclone.so");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("/nonexistent/libpheromesh_dds_cyclone.so is missing"), std::string::npos);
  const auto wrong = bus::load_transport_module("fastdds", PHEROMESH_DDS_MODULE_CYCLONE);
  ASSERT_FALSE(wrong);
  EXPECT_NE(wrong.error().message.find("it says 'cyclone'"), std::string::npos) << wrong.error().message;
  const auto not_a_module = bus::load_transport_module("cyclone", PHEROMESH_SOURCE_DIR "/README.md");
  ASSERT_FALSE(not_a_module);
  EXPECT_NE(not_a_module.error().message.find("cannot load the 'cyclone' DDS module"), std::string::npos);
}

class ModuleBus : public testing::TestWithParam<std::string> {};

// The module's bus (its own copy of the bus code, its vendor's library mapped
// by it alone) and the linked-in bus of the other vendor carry a view both ways.
TEST_P(ModuleBus, AModulesBusAndALinkedInBusOfTheOtherVendorCarryAViewBothWays) {
  const std::string vendor = GetParam();
  const std::string other = vendor == "cyclone" ? "fastdds" : "cyclone";
  const auto module = bus::load_transport_module(
      vendor, vendor == "cyclone" ? PHEROMESH_DDS_MODULE_CYCLONE : PHEROMESH_DDS_MODULE_FASTDDS);
  ASSERT_TRUE(module) << module.error().message;
  auto t = module.value()->make(options("module"));
  ASSERT_TRUE(t) << t.error().message;
  bus::Bus from_module(std::move(t).value());
  auto linked = bus::make_bus(other, options("linked"));
  ASSERT_TRUE(linked) << linked.error().message;
  for (auto [w, r] : {std::pair{&from_module, linked.value().get()}, std::pair{linked.value().get(), &from_module}}) {
    const uint32_t uav = w == &from_module ? 5 : 6;
    r->join_uav(uav, 3);
    core::ViewMsg view{uav, 12, {core::TileMsg{0, {1, 2}, 0, 0, 1, 1, {2.5F}}}, {}};
    std::vector<core::ViewMsg> got;
    const auto deadline = Clock::now() + std::chrono::seconds(15);
    ASSERT_TRUE(w->publish_view(view));
    while (got.empty() && Clock::now() < deadline) {
      r->take_views(got);
      if (got.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ASSERT_EQ(got.size(), 1U) << (w == &from_module ? "module -> linked" : "linked -> module");
    EXPECT_EQ(got[0].uav, uav);
    EXPECT_EQ(got[0].tick, 12U);
    ASSERT_EQ(got[0].tiles.size(), 1U);
    EXPECT_EQ(got[0].tiles[0].values, std::vector<float>{2.5F});
  }
}

INSTANTIATE_TEST_SUITE_P(Vendors, ModuleBus, testing::Values("cyclone", "fastdds"),
                         [](const auto& p) { return p.param; });
