// The Fast DDS bus's handling of received sample bytes without a participant
// (common/bus/src/fastdds_samples.hpp): what fuzz/fuzz_fastdds_samples.cpp
// found, kept as tests.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
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

TEST(FastDdsSamples, AWellFormedDepositBatchDeserializesAndConverts) {
  msg::Deposit first;
  first.uav(3);
  first.seq(7);
  first.region(1);
  first.kind(2);
  first.x(12);
  first.y(-4);
  first.amount(0.5F);
  msg::Deposit second = first;
  second.seq(8);
  second.kind(0);
  msg::DepositBatch in;
  in.forwarder(4);
  in.tick(9);
  in.deposits({first, second});
  msg::DepositBatchPubSubType plain;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(plain.m_typeSize);
  ASSERT_TRUE(plain.serialize(&in, &payload));
  msg::DepositBatch out;
  SafePubSub<msg::DepositBatchPubSubType> type;
  ASSERT_TRUE(type.deserialize(&payload, &out));
  const auto b = Convert<core::DepositBatchMsg>::in(out);
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->forwarder, 4U);
  EXPECT_EQ(b->tick, 9U);
  ASSERT_EQ(b->deposits.size(), 2U);
  const core::DepositMsg& d = b->deposits[0];
  EXPECT_EQ(d.uav, 3U);
  EXPECT_EQ(d.seq, 7U);
  EXPECT_EQ(d.region, 1U);
  EXPECT_EQ(d.kind, 2);
  EXPECT_EQ(d.cell.x, 12);
  EXPECT_EQ(d.cell.y, -4);
  EXPECT_FLOAT_EQ(d.amount, 0.5F);
  EXPECT_EQ(b->deposits[1].seq, 8U);
  EXPECT_EQ(b->deposits[1].kind, 0);
}

// The fuzz harness's committed seed of the deposit topic (its first byte
// picks the topic) is a well-formed batch of two deposits: the harness
// starts from a sample the receivers take.
TEST(FastDdsSamples, TheFuzzSeedOfTheDepositTopicIsAWellFormedBatch) {
  std::ifstream in(PHEROMESH_SOURCE_DIR "/fuzz/corpus/fuzz_fastdds_samples/seed-deposit", std::ios::binary);
  ASSERT_TRUE(in.good());
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 1U);
  EXPECT_EQ(bytes[0] % 15, 0) << "the harness's selector of the deposit topic";
  auto payload = payload_of({bytes.begin() + 1, bytes.end()});
  msg::DepositBatch s;
  SafePubSub<msg::DepositBatchPubSubType> type;
  ASSERT_TRUE(type.deserialize(&payload, &s));
  const auto b = Convert<core::DepositBatchMsg>::in(s);
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->forwarder, 2U);
  ASSERT_EQ(b->deposits.size(), 2U);
  EXPECT_EQ(b->deposits[0].seq, 4U);
  EXPECT_EQ(b->deposits[1].seq, 5U);
  EXPECT_EQ(b->deposits[1].cell.x, 3);
}

// A batch whose sequence is over MAX_FORWARD_DEPOSITS is not taken.
TEST(FastDdsSamples, ADepositBatchOverItsBoundIsNotConverted) {
  msg::DepositBatch over;
  over.deposits(std::vector<msg::Deposit>(core::kMaxForwardDeposits + 1));
  EXPECT_FALSE(Convert<core::DepositBatchMsg>::in(over).has_value());
  over.deposits().pop_back();
  EXPECT_TRUE(Convert<core::DepositBatchMsg>::in(over).has_value());
}

}  // namespace
}  // namespace pheromesh::bus::fastdds_samples
