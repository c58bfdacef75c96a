// Fuzz harness: the console's request parsing as pure functions
// (pheromesh/console/request.hpp, from the console hardening of issue 16):
// what the server decides from a request's head before reading its body
// (check_request_head), the /api/frame query (parse_frame_query), the
// /api/command body (parse_command_body, then parse_command) and the decimal
// numbers of a query (parse_decimal_u64). The first input byte picks one,
// the rest is read with FuzzedDataProvider. Built only when request.hpp
// exists (fuzz/CMakeLists.txt); fuzz_console_http drives the same code
// through a socket.
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "pheromesh/console/commands.hpp"
#include "pheromesh/console/request.hpp"

using namespace pheromesh;

namespace {

constexpr const char* kToken = "0123456789abcdef0123456789abcdef";

std::optional<std::string> maybe(FuzzedDataProvider& in) {
  if (!in.ConsumeBool()) return std::nullopt;
  return in.ConsumeRandomLengthString(64);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  FuzzedDataProvider in(data, size);
  switch (in.ConsumeIntegralInRange<int>(0, 3)) {
    case 0: {
      // Parameters as the HTTP library hands them over: any keys and values,
      // repeated keys included.
      console::QueryParams params;
      const int n = in.ConsumeIntegralInRange<int>(0, 8);
      for (int i = 0; i < n; ++i) {
        static constexpr const char* kKeys[] = {"layer", "since", "t", "wait", "token"};
        std::string key = in.ConsumeBool() ? std::string(kKeys[in.ConsumeIntegralInRange<int>(0, 4)])
                                           : in.ConsumeRandomLengthString(8);
        params.emplace(std::move(key), in.ConsumeRandomLengthString(32));
      }
      auto q = console::parse_frame_query(params);
      if (q) {
        if (q->t && !std::isfinite(*q->t)) __builtin_trap();  // the header promises a finite t
      } else if (q.error().message.empty()) {
        __builtin_trap();
      }
      break;
    }
    case 1: {
      const std::string body = in.ConsumeRemainingBytesAsString();
      auto j = console::parse_command_body(body);
      if (!j) {
        if (j.error().message.empty()) __builtin_trap();
        break;
      }
      if (!j->is_object()) __builtin_trap();  // "a JSON object, or an error"
      console::CommandContext ctx;
      ctx.uavs = 4;
      ctx.regions = 4;
      ctx.width = 30;
      ctx.height = 30;
      (void)console::parse_command(j.value(), ctx);
      break;
    }
    case 2: {
      const std::string method = in.ConsumeBool() ? (in.ConsumeBool() ? "GET" : "POST") : in.ConsumeRandomLengthString(8);
      const std::string path = in.ConsumeBool() ? (in.ConsumeBool() ? "/api/command" : "/api/frame")
                                                : in.ConsumeRandomLengthString(64);
      const auto length = maybe(in), encoding = maybe(in), content_encoding = maybe(in);
      std::optional<std::string> authorization;
      if (in.ConsumeBool()) {
        authorization = in.ConsumeBool() ? std::string("Bearer ") + kToken : in.ConsumeRandomLengthString(64);
      }
      console::RequestHead head;
      head.method = method;
      head.path = path;
      if (length) head.content_length = *length;
      if (encoding) head.transfer_encoding = *encoding;
      if (content_encoding) head.content_encoding = *content_encoding;
      if (authorization) head.authorization = *authorization;
      const std::string token = in.ConsumeBool() ? kToken : "";
      const auto max_body = in.ConsumeIntegralInRange<std::size_t>(0, 1 << 20);
      if (auto v = console::check_request_head(head, token, max_body)) {
        if (v->status < 400 || v->status > 599) __builtin_trap();  // a refusal is an error answer
      }
      break;
    }
    default: {
      const std::string s = in.ConsumeRemainingBytesAsString();
      if (auto v = console::parse_decimal_u64(s)) {
        // Digits only and within 64 bits: the number reads back as the text
        // without its leading zeros.
        const std::size_t first = s.find_first_not_of('0');
        const std::string digits = first == std::string::npos ? "0" : s.substr(first);
        if (std::to_string(*v) != digits) __builtin_trap();
      }
      break;
    }
  }
  return 0;
}
