#include "pheromesh/console/request.hpp"

#include <charconv>
#include <cmath>
#include <iterator>
#include <limits>
#include <utility>

namespace pheromesh::console {

const char* refusal_name(Refusal r) {
  switch (r) {
    case Refusal::Unauthorised:
      return "unauthorised";
    case Refusal::BodyTooLarge:
      return "body_too_large";
    case Refusal::LengthRequired:
      return "length_required";
    case Refusal::UnsupportedEncoding:
      return "unsupported_encoding";
    case Refusal::BadRequest:
      return "bad_request";
    case Refusal::HeadTooLarge:
      return "head_too_large";
    case Refusal::HeadTimeout:
      return "head_timeout";
    case Refusal::TooManyConnections:
      return "too_many_connections";
  }
  return "unknown";
}

bool same_token(std::string_view a, std::string_view b) {
  if (a.size() != b.size() || a.empty()) return false;
  unsigned char d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d |= static_cast<unsigned char>(a[i] ^ b[i]);
  return d == 0;
}

std::optional<uint64_t> parse_decimal_u64(std::string_view s) {
  if (s.empty() || s.size() > 20) return std::nullopt;
  uint64_t v = 0;
  for (const char c : s) {
    if (c < '0' || c > '9') return std::nullopt;
    const auto digit = static_cast<uint64_t>(c - '0');
    if (v > (std::numeric_limits<uint64_t>::max() - digit) / 10) return std::nullopt;
    v = v * 10 + digit;
  }
  return v;
}

std::optional<HeadVerdict> check_request_head(const RequestHead& h, const std::string& token, std::size_t max_body) {
  std::optional<uint64_t> length;
  if (h.content_length) {
    length = parse_decimal_u64(*h.content_length);
    if (!length) return HeadVerdict{400, Refusal::BadRequest, "Content-Length must be a decimal number"};
  }
  if (h.method == "POST" && h.path == "/api/command") {
    std::string_view given;
    if (h.authorization && h.authorization->substr(0, 7) == "Bearer ") given = h.authorization->substr(7);
    if (!same_token(given, token)) {
      return HeadVerdict{401, Refusal::Unauthorised,
                         token.empty() ? "this console takes no commands"
                                       : "missing or wrong token (use the URL the ground station printed)"};
    }
  }
  if (h.transfer_encoding) {
    return HeadVerdict{411, Refusal::LengthRequired, "send the body with a Content-Length, not a Transfer-Encoding"};
  }
  if (h.content_encoding && *h.content_encoding != "identity") {
    return HeadVerdict{415, Refusal::UnsupportedEncoding, "the body must not be compressed"};
  }
  if (length && *length > max_body) {
    return HeadVerdict{413, Refusal::BodyTooLarge, "the body is larger than " + std::to_string(max_body) + " bytes"};
  }
  const bool has_body_method = h.method == "POST" || h.method == "PUT" || h.method == "PATCH";
  if (has_body_method && !length) {
    return HeadVerdict{411, Refusal::LengthRequired, "a " + std::string(h.method) + " needs a Content-Length"};
  }
  return std::nullopt;
}

namespace {
const std::string* single(const QueryParams& p, const std::string& name, bool& repeated) {
  const auto [first, last] = p.equal_range(name);
  if (first == last) return nullptr;
  if (std::next(first) != last) repeated = true;
  return &first->second;
}
}  // namespace

core::Result<FrameQuery> parse_frame_query(const QueryParams& params) {
  FrameQuery q;
  bool repeated = false;
  if (const auto* s = single(params, "since", repeated)) {
    const auto v = parse_decimal_u64(*s);
    if (!v) return core::Error{"since must be a version: digits only, below 2^64"};
    q.since = *v;
  }
  if (const auto* s = single(params, "layer", repeated)) {
    const auto v = parse_decimal_u64(*s);
    if (!v || *v > std::numeric_limits<uint16_t>::max()) return core::Error{"layer must be a layer index, 0..65535"};
    q.layer = static_cast<uint16_t>(*v);
  }
  if (const auto* s = single(params, "t", repeated)) {
    double t = 0;
    const char* end = s->data() + s->size();
    const auto [p, ec] = std::from_chars(s->data(), end, t);
    if (s->empty() || ec != std::errc{} || p != end || !std::isfinite(t)) {
      return core::Error{"t must be a finite number of seconds"};
    }
    q.t = t;
  }
  if (const auto* s = single(params, "wait", repeated)) q.wait = *s == "1";
  if (repeated) return core::Error{"since, layer, t and wait may each be given once"};
  return q;
}

core::Result<nlohmann::json> parse_command_body(std::string_view body) {
  nlohmann::json j = nlohmann::json::parse(body, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    return core::Error{"the body must be a JSON object, e.g. {\"kind\":\"pause\"}"};
  }
  return j;
}

void RefusalLimiter::roll(double now_s) {
  if (window_start_s_ < 0) window_start_s_ = now_s;
  if (now_s - window_start_s_ < window_s_) return;
  suppressed_ended_ += suppressed_in_window_;
  suppressed_in_window_ = 0;
  in_window_ = 0;
  window_start_s_ = now_s;
}

bool RefusalLimiter::admit(double now_s) {
  roll(now_s);
  if (in_window_ < max_) {
    ++in_window_;
    return true;
  }
  ++suppressed_in_window_;
  return false;
}

void RefusalLimiter::suppress(uint64_t n, double now_s) {
  roll(now_s);
  suppressed_in_window_ += n;
}

std::optional<uint64_t> RefusalLimiter::take_suppressed(double now_s) {
  roll(now_s);
  if (suppressed_ended_ == 0) return std::nullopt;
  return std::exchange(suppressed_ended_, 0);
}

}  // namespace pheromesh::console
