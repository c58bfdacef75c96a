// The console's HTTP server: the page (embedded at build time), /api/info,
// /api/frame, /api/command and /metrics, over whatever ConsoleSource feeds
// it (the live ground station or a recording).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>

#include "pheromesh/console/request.hpp"
#include "pheromesh/core/result.hpp"

namespace pheromesh::console {

class ConsoleSource {
 public:
  virtual ~ConsoleSource() = default;
  virtual nlohmann::json info() = 0;
  // GET /api/frame. Live: with `wait`, blocks (at most 1 s) until a frame
  // newer than `since` exists. Replay: `t` picks the moment.
  virtual nlohmann::json frame(uint16_t layer, uint64_t since, std::optional<double> t, bool wait) = 0;
  struct Answer {
    int status = 200;
    std::string message;
  };
  // POST /api/command, already authorised; `who` names the client.
  virtual Answer command(const nlohmann::json& body, const std::string& who) = 0;
  virtual std::string metrics() = 0;
  // A request the server refused (no token, too large, too many long-polls,
  // too slow, ...), already counted in ServerStats. Called from the
  // server's threads, which it must not hold up: a source that logs or
  // records refusals queues them and rate-limits (RefusalLimiter).
  virtual void refused(Refusal /*reason*/, int /*status*/, const std::string& /*who*/, const std::string& /*what*/) {}
};

struct ServerOptions {
  std::string bind = "127.0.0.1";
  uint16_t port = 0;   // 0: any free port
  std::string token;   // required for POST /api/command; empty: commands refused
  HttpLimits limits;   // docs/console.md, "Limits"
};

struct ServerStats {
  uint64_t requests = 0;
  uint64_t frame_requests = 0;
  uint64_t body_bytes = 0;  // response bodies before compression
  uint64_t commands_unauthorised = 0;  // = refused[Refusal::Unauthorised]
  RefusalCounts refused{};              // by Refusal
  uint64_t open_connections = 0;
  // Long-polls answered at once, not held: their client (or all clients)
  // already held as many as allowed.
  uint64_t long_polls_unheld = 0;
};

class ConsoleServer {
 public:
  ConsoleServer(ConsoleSource& source, ServerOptions options);
  ~ConsoleServer();
  ConsoleServer(const ConsoleServer&) = delete;
  ConsoleServer& operator=(const ConsoleServer&) = delete;

  // Binds and starts serving in a thread; returns the bound port.
  core::Result<uint16_t> start();
  void stop();
  [[nodiscard]] ServerStats stats() const;
  // http://HOST:PORT/?token=TOKEN
  [[nodiscard]] std::string url() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A random token of 32 hex digits (from /dev/urandom).
std::string random_token();

}  // namespace pheromesh::console
