// /metrics latency of a running web console with no other clients (the
// baseline) and then with N slow or idle connections open, in the same run:
// half of them connect and send nothing, half send a request head that
// never ends, one more byte every second. Raw sockets, so that requests
// can be left unfinished. Prints p50 / p99 / max for both.
// usage: pheromesh-bench-console --port P [--host 127.0.0.1] [--slow 50] [--requests 200]
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

int connect_to(const std::string& host, uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  inet_pton(AF_INET, host.c_str(), &a.sin_addr);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

// One GET /metrics on a new connection; its time [ms], or a negative
// number if it was not answered with 200 within 10 s.
double metrics_ms(const std::string& host, uint16_t port) {
  const auto t0 = Clock::now();
  const int fd = connect_to(host, port);
  if (fd < 0) return -1;
  const std::string req = "GET /metrics HTTP/1.1\r\nHost: bench\r\nConnection: close\r\n\r\n";
  if (::send(fd, req.data(), req.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(req.size())) {
    ::close(fd);
    return -1;
  }
  std::string in;
  char buf[16384];
  for (;;) {  // Connection: close: the answer ends when the server closes
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 10000) <= 0) break;
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    in.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  return in.rfind("HTTP/1.1 200", 0) == 0 ? ms : -ms;
}

struct Figures {
  double p50 = 0, p99 = 0, max = 0;
  int failed = 0;
};

Figures measure(const std::string& host, uint16_t port, int n) {
  std::vector<double> v;
  Figures f;
  for (int i = 0; i < n; ++i) {
    const double ms = metrics_ms(host, port);
    if (ms < 0) ++f.failed;
    v.push_back(std::abs(ms));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // a scraper, not a flood
  }
  std::sort(v.begin(), v.end());
  const auto at = [&v](double q) {
    return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
  };
  f.p50 = at(0.5);
  f.p99 = at(0.99);
  f.max = v.back();
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"/metrics latency of a web console, alone and with slow or idle connections open"};
  std::string host = "127.0.0.1";
  uint16_t port = 0;
  int slow = 50, requests = 200;
  app.add_option("--host", host)->capture_default_str();
  app.add_option("--port", port)->required();
  app.add_option("--slow", slow, "Slow or idle connections held open")->capture_default_str();
  app.add_option("--requests", requests, "/metrics requests per measurement")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  CLI11_PARSE(app, argc, argv);

  const Figures base = measure(host, port, requests);
  std::vector<int> fds;
  for (int i = 0; i < slow; ++i) {
    const int fd = connect_to(host, port);
    if (fd < 0) continue;
    if (i % 2 == 1) {
      const std::string head = "GET /metrics HTTP/1.1\r\nHost: bench\r\nX-Slow: ";
      (void)::send(fd, head.data(), head.size(), MSG_NOSIGNAL);
    }
    fds.push_back(fd);
  }
  std::atomic<bool> done{false};
  // Trickle: one byte a second on every slow connection (the idle ones too:
  // their first byte starts a head), reconnecting those the server closed,
  // so that N stay open throughout.
  std::atomic<int> reopened{0};
  std::thread trickle([&] {
    while (!done) {
      for (auto& fd : fds) {
        if (::send(fd, "a", 1, MSG_NOSIGNAL) != 1) {
          ::close(fd);
          fd = connect_to(host, port);
          ++reopened;
        }
      }
      for (int i = 0; i < 10 && !done; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const Figures loaded = measure(host, port, requests);
  done = true;
  trickle.join();
  for (const int fd : fds) ::close(fd);

  std::printf("console /metrics latency, %d requests each, %s:%u\n", requests, host.c_str(), port);
  std::printf("  no other clients:          p50 %7.2f ms  p99 %7.2f ms  max %7.2f ms  failed %d\n", base.p50, base.p99,
              base.max, base.failed);
  std::printf(
      "  %3zu slow/idle connections: p50 %7.2f ms  p99 %7.2f ms  max %7.2f ms  failed %d (slow ones reopened: %d)\n",
      fds.size(), loaded.p50, loaded.p99, loaded.max, loaded.failed, reopened.load());
  std::printf("  ratio loaded/baseline: p50 %.2f  p99 %.2f\n", loaded.p50 / std::max(base.p50, 1e-6),
              loaded.p99 / std::max(base.p99, 1e-6));
  return loaded.failed == 0 && base.failed == 0 ? 0 : 1;
}
