// Fuzz harness: the console's HTTP request handling as it is served — a real
// console::ConsoleServer on 127.0.0.1 (started once), one keep-alive client.
// The first input byte picks the request, the rest is its payload:
//   0: GET /api/frame?<payload>, the payload percent-encoded where a query
//      needs it, so every byte reaches the server's parameter parsing
//      (since, layer, t, wait);
//   1: POST /api/command with the token, the payload as body;
//   2: POST /api/command without the token, the payload as body.
// The source behind it answers from a fixed state and checks what the server
// hands it; a 5xx answer (a handler threw) or a dead server is a crash.
//
// The HTTP server is being hardened (issue 16); when its parsing becomes pure
// functions (parse_frame_query, ...), they get a direct harness like
// fuzz_console_command and this one stays as the end-to-end check.
#include <httplib.h>

#include <atomic>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "pheromesh/console/commands.hpp"
#include "pheromesh/console/server.hpp"
#include "pheromesh/web/assets.hpp"

// The page is not part of what is fuzzed; the fuzz tree does not build it.
namespace pheromesh::web {
const Asset* find_asset(std::string_view /*path*/) { return nullptr; }
}  // namespace pheromesh::web

using namespace pheromesh;

namespace {

constexpr const char* kToken = "0123456789abcdef0123456789abcdef";

class Source final : public console::ConsoleSource {
 public:
  nlohmann::json info() override { return {{"name", "fuzz"}}; }
  nlohmann::json frame(uint16_t layer, uint64_t since, std::optional<double> t, bool wait) override {
    if (wait) return {{"version", 1}};  // never block: the live source waits up to 1 s
    return {{"layer", layer}, {"since", since}, {"t", t ? *t : -1.0}};
  }
  Answer command(const nlohmann::json& body, const std::string& /*who*/) override {
    console::CommandContext ctx;
    ctx.uavs = 4;
    ctx.regions = 4;
    ctx.width = 30;
    ctx.height = 30;
    const auto p = console::parse_command(body, ctx);
    if (p.command) return {200, "ok " + p.what};
    return p.refusal;
  }
  std::string metrics() override { return "pheromesh_fuzz 1\n"; }
};

struct Fixture {
  Source source;
  std::unique_ptr<console::ConsoleServer> server;
  std::unique_ptr<httplib::Client> client;
  Fixture() {
    server = std::make_unique<console::ConsoleServer>(source, console::ServerOptions{"127.0.0.1", 0, kToken});
    auto port = server->start();
    if (!port) {
      std::fprintf(stderr, "fuzz_console_http: %s\n", port.error().message.c_str());
      std::abort();
    }
    client = std::make_unique<httplib::Client>("127.0.0.1", port.value());
    client->set_keep_alive(false);
    client->set_read_timeout(5, 0);
  }
};

Fixture& fixture() {
  static Fixture* f = new Fixture();  // never destroyed: the server thread outlives main's statics
  return *f;
}

std::string query_encode(const uint8_t* p, std::size_t n) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = p[i];
    if (std::isalnum(c) != 0 || c == '&' || c == '=' || c == '-' || c == '.' || c == '_' || c == '~' || c == '+') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4U];
      out += kHex[c & 15U];
    }
  }
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  Fixture& f = fixture();
  const std::string payload(reinterpret_cast<const char*>(data + 1), size - 1);
  const auto request = [&]() -> httplib::Result {
    switch (data[0] % 3) {
      case 0:
        return f.client->Get(("/api/frame?" + query_encode(data + 1, size - 1)).c_str());
      case 1:
        return f.client->Post("/api/command", httplib::Headers{{"Authorization", std::string("Bearer ") + kToken}},
                              payload, "application/json");
      default:
        return f.client->Post("/api/command", payload, "application/json");
    }
  };
  const httplib::Result res = request();
  if (!res) {
    std::fprintf(stderr, "fuzz_console_http: no answer (%s)\n", httplib::to_string(res.error()).c_str());
    std::abort();
  }
  if (res->status >= 500) {
    std::fprintf(stderr, "fuzz_console_http: status %d: %s\n", res->status, res->body.c_str());
    __builtin_trap();
  }
  // Every answer of the API is JSON.
  if (nlohmann::json::parse(res->body, nullptr, false).is_discarded()) __builtin_trap();
  return 0;
}
