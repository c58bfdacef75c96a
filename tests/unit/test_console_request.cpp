// The console's request checks (console/request.hpp): what is refused from
// the head alone, the frame query, the command body, and the rate limit of
// the refusal log.
#include <gtest/gtest.h>

#include "pheromesh/console/request.hpp"
#include "pheromesh/console/swarm_metrics.hpp"

namespace pheromesh::console {
namespace {

const std::string kToken = "0123456789abcdef0123456789abcdef";
const std::string kBearer = "Bearer " + kToken;

RequestHead post(std::optional<std::string_view> length, std::optional<std::string_view> auth) {
  RequestHead h;
  h.method = "POST";
  h.path = "/api/command";
  h.content_length = length;
  h.authorization = auth;
  return h;
}

TEST(ConsoleRequestHead, TheTokenIsCheckedFirstWhateverTheBodysSize) {
  auto v = check_request_head(post("1073741824", std::nullopt), kToken, 65536);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->status, 401);
  EXPECT_EQ(v->reason, Refusal::Unauthorised);
  v = check_request_head(post("20", "Bearer wrong"), kToken, 65536);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->status, 401);
  v = check_request_head(post("20", kBearer), "", 65536);
  ASSERT_TRUE(v) << "an empty token takes no commands";
  EXPECT_EQ(v->message, "this console takes no commands");
  EXPECT_FALSE(check_request_head(post("20", kBearer), kToken, 65536));
}

TEST(ConsoleRequestHead, BodiesAboveTheCapOfUnknownLengthOrCompressedAreRefused) {
  const auto status = [](RequestHead h) {
    const auto v = check_request_head(h, kToken, 1000);
    return v ? v->status : 0;
  };
  EXPECT_EQ(status(post("1000", kBearer)), 0);
  EXPECT_EQ(status(post("1001", kBearer)), 413);
  EXPECT_EQ(status(post("99999999999999999999999", kBearer)), 400) << "does not fit 64 bits";
  EXPECT_EQ(status(post("-1", kBearer)), 400);
  EXPECT_EQ(status(post(std::nullopt, kBearer)), 411);
  auto chunked = post(std::nullopt, kBearer);
  chunked.transfer_encoding = "chunked";
  EXPECT_EQ(status(chunked), 411);
  auto gz = post("10", kBearer);
  gz.content_encoding = "gzip";
  EXPECT_EQ(status(gz), 415);
  RequestHead g;
  g.method = "GET";
  g.path = "/metrics";
  EXPECT_EQ(status(g), 0);
  g.content_length = "5000";
  EXPECT_EQ(status(g), 413) << "a GET with a large body is not read either";
}

TEST(ConsoleRequestNumbers, DecimalsAreDigitsOnlyAndFit64Bits) {
  EXPECT_EQ(parse_decimal_u64("0"), 0U);
  EXPECT_EQ(parse_decimal_u64("18446744073709551615"), UINT64_MAX);
  EXPECT_FALSE(parse_decimal_u64("18446744073709551616"));
  EXPECT_FALSE(parse_decimal_u64("-1"));
  EXPECT_FALSE(parse_decimal_u64("+1"));
  EXPECT_FALSE(parse_decimal_u64(" 1"));
  EXPECT_FALSE(parse_decimal_u64("1e3"));
  EXPECT_FALSE(parse_decimal_u64(""));
}

TEST(ConsoleRequestFrameQuery, ReadsEachFieldAndRefusesWhatDoesNotFit) {
  auto q = parse_frame_query({{"since", "42"}, {"layer", "3"}, {"wait", "1"}, {"t", "2.5"}});
  ASSERT_TRUE(q);
  EXPECT_EQ(q->since, 42U);
  EXPECT_EQ(q->layer, 3);
  EXPECT_TRUE(q->wait);
  EXPECT_DOUBLE_EQ(*q->t, 2.5);
  q = parse_frame_query({});
  ASSERT_TRUE(q);
  EXPECT_EQ(q->since, 0U);
  EXPECT_FALSE(q->wait);
  EXPECT_FALSE(q->t);
  for (const QueryParams& bad :
       {QueryParams{{"layer", "65536"}}, QueryParams{{"layer", "4294967296"}}, QueryParams{{"layer", "-1"}},
        QueryParams{{"since", "-1"}}, QueryParams{{"since", "18446744073709551616"}}, QueryParams{{"t", "nan"}},
        QueryParams{{"t", "inf"}}, QueryParams{{"t", "1x"}}, QueryParams{{"t", ""}},
        QueryParams{{"since", "1"}, {"since", "2"}}}) {
    EXPECT_FALSE(parse_frame_query(bad)) << bad.begin()->first << "=" << bad.begin()->second;
  }
}

TEST(ConsoleRequestCommandBody, OnlyAJsonObjectIsACommand) {
  EXPECT_TRUE(parse_command_body(R"({"kind":"pause"})"));
  EXPECT_FALSE(parse_command_body("[1,2]"));
  EXPECT_FALSE(parse_command_body(R"({"kind":)"));
  EXPECT_FALSE(parse_command_body(""));
  EXPECT_FALSE(parse_command_body(std::string(10000, '[')));
}

TEST(ConsoleRefusalLimiter, LogsAtMostNPerWindowAndSummarisesTheRestOnce) {
  RefusalLimiter l(5, 10.0);
  int logged = 0;
  for (int i = 0; i < 20; ++i) logged += l.admit(1.0 + 0.1 * i) ? 1 : 0;
  EXPECT_EQ(logged, 5);
  EXPECT_FALSE(l.take_suppressed(5.0)) << "the window has not ended";
  l.suppress(3, 6.0);  // queue overflow: counted, never described
  EXPECT_EQ(l.take_suppressed(11.5), 18U);
  EXPECT_FALSE(l.take_suppressed(12.0)) << "once";
  EXPECT_TRUE(l.admit(12.0)) << "a new window logs again";
}

TEST(ConsoleRefusalLimiter, RefusalsAreInMetricsByReason) {
  SwarmCounters c;
  RefusalCounts r{};
  r[static_cast<std::size_t>(Refusal::Unauthorised)] = 20;
  r[static_cast<std::size_t>(Refusal::TooManyConnections)] = 2;
  c.http_refused = r;
  c.http_connections = 7;
  c.http_long_polls_unheld = 3;
  const std::string text = swarm_metrics_text(ConsoleState{}, c);
  EXPECT_NE(text.find("pheromesh_console_http_refused_total{reason=\"unauthorised\"} 20\n"), std::string::npos) << text;
  EXPECT_NE(text.find("pheromesh_console_http_refused_total{reason=\"too_many_connections\"} 2\n"), std::string::npos);
  EXPECT_NE(text.find("pheromesh_console_http_refused_total{reason=\"head_timeout\"} 0\n"), std::string::npos);
  EXPECT_NE(text.find("pheromesh_console_http_connections 7\n"), std::string::npos);
  EXPECT_NE(text.find("pheromesh_console_http_long_polls_unheld_total 3\n"), std::string::npos);
  EXPECT_EQ(text.find("too_many_long_polls"), std::string::npos) << "a long-poll beyond the limits is not refused";
}

}  // namespace
}  // namespace pheromesh::console
