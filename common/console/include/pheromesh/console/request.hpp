// The console's HTTP requests read as data, before anything acts on them:
// what to refuse from the request line and headers alone (so that a body is
// never read for a request that will be refused), the query of /api/frame,
// the body of /api/command, and the limits the server holds to
// (docs/console.md, "Limits"). Pure: no sockets, no clock of its own, so it
// can be unit-tested and fuzzed on its own.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "pheromesh/core/result.hpp"

namespace pheromesh::console {

struct HttpLimits {
  std::size_t max_body = 64 * 1024;          // [byte] a request body (commands are < 200 bytes)
  std::size_t max_head = 16 * 1024;          // [byte] request line and headers
  unsigned threads = 8;                      // requests served at once
  unsigned max_connections = 256;            // open connections, all clients
  unsigned max_connections_per_client = 64;  // open connections from one address
  unsigned long_polls_per_client = 4;        // /api/frame?wait=1 held at once for one address
  double head_timeout_s = 10;                // [s] from connecting (or the previous answer) to the end of the headers
  double idle_timeout_s = 5;                 // [s] an idle keep-alive connection is closed after this
  double read_timeout_s = 5;                 // [s] waiting for one read of a body
  double write_timeout_s = 5;                // [s] waiting for the client to take one write of an answer
  unsigned max_requests_per_connection = 100;
};

// Why the console refused a request; each is counted and is a label of
// pheromesh_console_http_refused_total.
enum class Refusal : uint8_t {
  Unauthorised,         // 401: POST /api/command without the token
  BodyTooLarge,         // 413: Content-Length above HttpLimits::max_body
  LengthRequired,       // 411: a body without Content-Length (chunked or until EOF)
  UnsupportedEncoding,  // 415: a compressed body
  BadRequest,           // 400: an unreadable request line, header or query
  HeadTooLarge,         // 431: request line and headers above HttpLimits::max_head
  HeadTimeout,          // the headers did not arrive in time: connection closed
  TooManyConnections,   // 503 or closed: connection limits
};
inline constexpr std::size_t kRefusalKinds = 8;
const char* refusal_name(Refusal r);  // "unauthorised", "body_too_large", ...
using RefusalCounts = std::array<uint64_t, kRefusalKinds>;

// The parts of a request known before its body is read.
struct RequestHead {
  std::string_view method, path;
  std::optional<std::string_view> content_length, transfer_encoding, content_encoding, authorization;
};

struct HeadVerdict {
  int status = 400;
  Refusal reason = Refusal::BadRequest;
  std::string message;
};

// What to answer before the body is read; nullopt: read the body (at most
// max_body bytes) and route the request. A refused request's body is never
// read, and the connection is closed after the answer. POST /api/command
// is checked for the token first, so a body of any size without a token
// gets 401; an empty `token` means the console takes no commands.
std::optional<HeadVerdict> check_request_head(const RequestHead& head, const std::string& token, std::size_t max_body);

// Constant time in the length of the strings.
bool same_token(std::string_view a, std::string_view b);

// A decimal number of digits only (no sign, no spaces, no exponent) that
// fits in 64 bits; nullopt otherwise. std::stoull takes "-1" as 2^64 - 1.
std::optional<uint64_t> parse_decimal_u64(std::string_view s);

// GET /api/frame?layer=L&since=V&t=SECONDS&wait=1 (docs/console.md).
struct FrameQuery {
  uint16_t layer = 0;
  uint64_t since = 0;
  std::optional<double> t;  // [s] replay only; finite
  bool wait = false;
};
using QueryParams = std::multimap<std::string, std::string>;  // as the HTTP library hands them over
core::Result<FrameQuery> parse_frame_query(const QueryParams& params);

// The body of POST /api/command: a JSON object, or an error that says what
// is expected. Numbers are not checked here (parse_command does that).
core::Result<nlohmann::json> parse_command_body(std::string_view body);

// Refused requests go to the log and the recording at most `max_per_window`
// times a window; the rest are counted and summarised once the window ends
// ("suppressed K"), so a flood of refused requests cannot fill either.
// Times are the caller's [s], non-decreasing.
class RefusalLimiter {
 public:
  RefusalLimiter(uint32_t max_per_window, double window_s) : max_(max_per_window), window_s_(window_s) {}
  // true: log and record this refusal; false: it is only counted.
  bool admit(double now_s);
  // `n` refusals that are only counted (they were never described).
  void suppress(uint64_t n, double now_s);
  // How many were not logged in windows that have ended, once; nullopt if none.
  std::optional<uint64_t> take_suppressed(double now_s);

 private:
  void roll(double now_s);
  uint32_t max_;
  double window_s_;
  double window_start_s_ = -1;
  uint32_t in_window_ = 0;
  uint64_t suppressed_in_window_ = 0, suppressed_ended_ = 0;
};

}  // namespace pheromesh::console
