// The typed bus over the DDS vendors: misuse is the same error on every
// vendor, and Writer<M> / Reader<M> carry a topic between any two vendors
// without a method of their own on Bus (domain 66, loopback; the integration
// tests use none of the bus tests' domains, 60 and 66).
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "pheromesh/bus/bus.hpp"
#include "pheromesh/bus/memory.hpp"
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

// Counts how a transport hands over each sample (TakeSink): its own,
// converted for the take (sample_owned: the typed reader moves it, a view's
// tiles are not copied again), or shared with other readers (sample).
class HandOver final : public TakeSink {
 public:
  void sample(const void* message, const SampleInfo& /*info*/) override {
    ++shared;
    got.push_back(*static_cast<const core::ViewMsg*>(message));
  }
  void sample_owned(void* message, const SampleInfo& /*info*/) override {
    ++owned;
    got.push_back(std::move(*static_cast<core::ViewMsg*>(message)));
  }
  void gone(const void* /*key_message*/, const SampleInfo& /*info*/) override {}
  int shared = 0, owned = 0;
  std::vector<core::ViewMsg> got;
};

TEST(TypedBusVendors, ADdsTransportHandsOverTheSampleItConvertedToBeMovedAndTheInMemoryOneSharesIt) {
  const core::ViewMsg view{7, 3, {core::TileMsg{0, {1, 2}, 3, 0, 2, 1, {0.5F, 1.5F}}}, {}};
  const auto take_one = [&](Bus& writer_bus, Bus& reader_bus, HandOver& sink) {
    const EndpointId reader = reader_bus.transport().open_reader(TopicKind::View, {"u.7"}, Watch::Samples);
    Writer<core::ViewMsg> writer(writer_bus);
    ASSERT_TRUE(writer.write(view, "u.7"));
    const EndpointId ids[] = {reader};
    const auto deadline = Clock::now() + std::chrono::seconds(15);
    while (sink.got.empty() && Clock::now() < deadline) {
      reader_bus.transport().wait(ids, Clock::now() + std::chrono::milliseconds(100));
      reader_bus.transport().take(reader, sink);
    }
  };
  for (const char* vendor : {"cyclone", "fastdds"}) {
    auto w = open(vendor, "writer");
    auto r = open(vendor, "reader");
    ASSERT_TRUE(w && r);
    HandOver sink;
    take_one(*w, *r, sink);
    ASSERT_EQ(sink.got.size(), 1U) << vendor;
    EXPECT_EQ(sink.owned, 1) << vendor;
    EXPECT_EQ(sink.shared, 0) << vendor;
    ASSERT_EQ(sink.got[0].tiles.size(), 1U);
    EXPECT_EQ(sink.got[0].tiles[0].values, (std::vector<float>{0.5F, 1.5F})) << vendor;
  }
  const auto domain = make_memory_domain();
  auto w = make_memory_bus(domain);
  auto r = make_memory_bus(domain);
  HandOver sink;
  take_one(*w, *r, sink);
  ASSERT_EQ(sink.got.size(), 1U);
  EXPECT_EQ(sink.shared, 1) << "one message for every reader of the process";
  EXPECT_EQ(sink.owned, 0);
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
