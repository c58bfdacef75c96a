// The Fast DDS bus's handling of received sample bytes without a participant
// (common/bus/src/fastdds_samples.hpp): what fuzz/fuzz_fastdds_samples.cpp
// found, kept as tests.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include <fastcdr/exceptions/Exception.h>

#include "fastdds_samples.hpp"

namespace pheromesh::bus::fastdds_samples {
namespace {

eprosima::fastrtps::rtps::SerializedPayload_t payload_of(const std::vector<uint8_t>& bytes) {
  eprosima::fastrtps::rtps::SerializedPayload_t p(static_cast<uint32_t>(bytes.size()));
  std::memcpy(p.data, bytes.data(), bytes.size());
  p.length = static_cast<uint32_t>(bytes.size());
  return p;
}

// fuzz/corpus/fuzz_fastdds_samples/regress-bad-encapsulation: "<<" (the
// harness's first byte picked the topic; the payload was one byte).
TEST(FastDdsSamples, APayloadWithoutCdrEncapsulationIsRefusedNotThrown) {
  for (const auto& bytes : {std::vector<uint8_t>{'<'}, std::vector<uint8_t>{0x3c, 0x3c, 0, 0},
                            std::vector<uint8_t>{0x00, 0x7f, 0, 0, 1, 2, 3, 4}}) {
    auto payload = payload_of(bytes);
    msg::Deposit d;
    SafePubSub<msg::DepositPubSubType> type;
    bool ok = true;
    EXPECT_NO_THROW(ok = type.deserialize(&payload, &d));
    EXPECT_FALSE(ok);
  }
}

// The guard: the generated type support alone lets the exception out, which
// is what terminated a receiving process.
TEST(FastDdsSamples, GuardTheGeneratedTypeSupportThrowsOnTheSamePayload) {
  auto payload = payload_of({0x3c, 0x3c, 0, 0});
  msg::Deposit d;
  msg::DepositPubSubType type;
  EXPECT_THROW(type.deserialize(&payload, &d), eprosima::fastcdr::exception::Exception);
}

TEST(FastDdsSamples, AWellFormedDepositDeserializesAndConverts) {
  msg::Deposit in;
  in.uav(3);
  in.seq(7);
  in.region(1);
  in.kind(2);
  in.x(12);
  in.y(-4);
  in.amount(0.5F);
  msg::DepositPubSubType plain;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(plain.m_typeSize);
  ASSERT_TRUE(plain.serialize(&in, &payload));
  msg::Deposit out;
  SafePubSub<msg::DepositPubSubType> type;
  ASSERT_TRUE(type.deserialize(&payload, &out));
  const auto d = Convert<core::DepositMsg>::in(out);
  ASSERT_TRUE(d.has_value());
  EXPECT_EQ(d->uav, 3U);
  EXPECT_EQ(d->seq, 7U);
  EXPECT_EQ(d->region, 1U);
  EXPECT_EQ(d->kind, 2);
  EXPECT_EQ(d->cell.x, 12);
  EXPECT_EQ(d->cell.y, -4);
  EXPECT_FLOAT_EQ(d->amount, 0.5F);
}

}  // namespace
}  // namespace pheromesh::bus::fastdds_samples
