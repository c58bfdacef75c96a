// The typed bus over the DDS vendors: misuse is the same error on every
// vendor, and Writer<M> / Reader<M> carry a topic between any two vendors
// without a method of their own on Bus (domain 66, loopback; the integration
// tests use none of the bus tests' domains, 60 and 66).
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/typed.hpp"

namespace pheromesh::bus {
namespace {

using Clock = std::chrono::steady_clock;

std::unique_ptr<Bus> open(const std::string& vendor, const std::string& name) {
  BusOptions o;
  o.process_name = name;
  o.domain = 66;
  auto b = make_bus(vendor, o);
  EXPECT_TRUE(static_cast<bool>(b)) << (b ? "" : b.error().message);
  return b ? std::move(b).value() : nullptr;
}

TEST(TypedBusVendors, AStatePublishedBeforeJoiningIsTheSameMisuseOnBothVendors) {
  for (const char* vendor : {"cyclone", "fastdds"}) {
    auto b = open(vendor, "misuse");
    ASSERT_TRUE(b);
    EXPECT_EQ(b->vendor(), vendor);
    EXPECT_THROW(b->publish_uav_state({}), BusMisuse) << vendor;
    EXPECT_EQ(b->matched_state_readers(), 0U) << vendor;
  }
}

TEST(TypedBusVendors, ATypedWriterAndReaderCarryDetectionsBetweenEveryPairOfVendors) {
  for (const char* w : {"cyclone", "fastdds"}) {
    for (const char* r : {"cyclone", "fastdds"}) {
      auto writer_bus = open(w, "writer");
      auto reader_bus = open(r, "reader");
      ASSERT_TRUE(writer_bus && reader_bus);
      Reader<core::DetectionMsg> reader(*reader_bus, {"x.typed"});
      Writer<core::DetectionMsg> writer(*writer_bus);
      ASSERT_TRUE(writer.write({4, 21, 3, {-2, 9}}, "x.typed"));
      std::vector<core::DetectionMsg> got;
      const auto deadline = Clock::now() + std::chrono::seconds(15);
      while (got.empty() && Clock::now() < deadline) {
        reader.wait(Clock::now() + std::chrono::milliseconds(100));
        reader.take(got);
      }
      ASSERT_EQ(got.size(), 1U) << w << " -> " << r;
      EXPECT_EQ(got[0].uav, 4U);
      EXPECT_EQ(got[0].tick, 21U);
      EXPECT_EQ(got[0].target, 3);
      EXPECT_EQ(got[0].cell.x, -2);
      EXPECT_EQ(got[0].cell.y, 9);
      EXPECT_EQ(writer.matched("x.typed"), 1U);
    }
  }
}

}  // namespace
}  // namespace pheromesh::bus
