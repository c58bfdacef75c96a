// The console's HTTP server against hostile clients (docs/console.md,
// "Limits"): a real ConsoleServer on loopback, raw sockets as the clients,
// so that requests can be cut short, sent slowly or never finished.
// Assertions are on answers and counters, never on time; the timeouts
// here only stop a broken server from hanging the test.
#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "pheromesh/console/server.hpp"

namespace pheromesh::console {
namespace {

using namespace std::chrono_literals;

const std::string kToken = "0123456789abcdef0123456789abcdef";

// Answers like the live console; long-polls block until released (or 20 s),
// so that the test decides how long they hold a worker.
class FakeSource final : public ConsoleSource {
 public:
  nlohmann::json info() override { return {{"mode", "live"}}; }
  nlohmann::json frame(uint16_t layer, uint64_t since, std::optional<double>, bool wait) override {
    std::unique_lock lock(mu_);
    if (wait) {
      ++waiting_;
      cv_.notify_all();
      cv_.wait_for(lock, 20s, [&] { return released_; });
      --waiting_;
    }
    return {{"version", 7}, {"layer", layer}, {"since", since}};
  }
  Answer command(const nlohmann::json& body, const std::string&) override {
    std::lock_guard lock(mu_);
    commands_.push_back(body);
    return {200, "done"};
  }
  std::string metrics() override { return "pheromesh_tick 1\n"; }
  void refused(Refusal reason, int status, const std::string&, const std::string&) override {
    std::lock_guard lock(mu_);
    refusals_.emplace_back(reason, status);
  }

  void release() {
    std::lock_guard lock(mu_);
    released_ = true;
    cv_.notify_all();
  }
  bool wait_for_waiting(int n) {
    std::unique_lock lock(mu_);
    return cv_.wait_for(lock, 20s, [&] { return waiting_ >= n; });
  }
  std::vector<nlohmann::json> commands() {
    std::lock_guard lock(mu_);
    return commands_;
  }
  std::vector<std::pair<Refusal, int>> refusals() {
    std::lock_guard lock(mu_);
    return refusals_;
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  bool released_ = false;
  int waiting_ = 0;
  std::vector<nlohmann::json> commands_;
  std::vector<std::pair<Refusal, int>> refusals_;
};

int connect_to(uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

bool send_all(int fd, const std::string& s) {
  std::size_t sent = 0;
  while (sent < s.size()) {
    const ssize_t n = ::send(fd, s.data() + sent, s.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return false;
    sent += static_cast<std::size_t>(n);
  }
  return true;
}

// One answer: its head and Content-Length bytes of body, or what arrived
// before the connection closed or `limit` passed ("" if nothing).
std::string read_answer(int fd, std::chrono::milliseconds limit = 10s) {
  std::string in;
  const auto until = std::chrono::steady_clock::now() + limit;
  for (;;) {
    const auto head_end = in.find("\r\n\r\n");
    if (head_end != std::string::npos) {
      const auto cl = in.find("Content-Length: ");
      const std::size_t len = cl == std::string::npos || cl > head_end ? 0 : std::stoul(in.substr(cl + 16));
      if (in.size() >= head_end + 4 + len) return in;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
    if (left.count() <= 0) return in;
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) return in;
    char buf[4096];
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) return in;
    in.append(buf, static_cast<std::size_t>(n));
  }
}

int status_of(const std::string& answer) { return answer.size() > 12 ? std::stoi(answer.substr(9, 3)) : 0; }

// A request on a new connection; its status (0: no answer).
int request(uint16_t port, const std::string& text, std::string* answer = nullptr) {
  const int fd = connect_to(port);
  if (fd < 0) return 0;
  send_all(fd, text);
  const std::string a = read_answer(fd);
  ::close(fd);
  if (answer) *answer = a;
  return status_of(a);
}

std::string get(const std::string& path) { return "GET " + path + " HTTP/1.1\r\nHost: t\r\n\r\n"; }

std::string post_command(const std::string& body, const std::string& token) {
  return "POST /api/command HTTP/1.1\r\nHost: t\r\nContent-Type: application/json\r\n" +
         (token.empty() ? "" : "Authorization: Bearer " + token + "\r\n") +
         "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

std::size_t count(Refusal r, const ServerStats& s) { return s.refused[static_cast<std::size_t>(r)]; }

struct Console {
  explicit Console(HttpLimits limits = {}) : server(source, ServerOptions{"127.0.0.1", 0, kToken, limits}) {
    auto p = server.start();
    EXPECT_TRUE(p) << (p ? "" : p.error().message);
    port = p ? p.value() : 0;
  }
  ~Console() {
    source.release();
    server.stop();
  }
  FakeSource source;
  ConsoleServer server;
  uint16_t port = 0;
};

TEST(ConsoleServerLimits, AHugePostWithoutTheTokenIsRefusedBeforeItsBodyIsRead) {
  Console c;
  const int fd = connect_to(c.port);
  ASSERT_GE(fd, 0);
  // 1 GiB announced, 8 KiB sent: a server that reads the body first waits
  // for the rest (and would answer 400 after its read timeout, not 401).
  ASSERT_TRUE(send_all(fd,
                       "POST /api/command HTTP/1.1\r\nHost: t\r\nContent-Type: application/json\r\n"
                       "Content-Length: 1073741824\r\n\r\n" +
                           std::string(8192, 'x')));
  const std::string a = read_answer(fd);
  EXPECT_EQ(status_of(a), 401) << a;
  EXPECT_NE(a.find("Connection: close"), std::string::npos) << "the unread body is not a request: the connection ends";
  EXPECT_NE(a.find("missing or wrong token"), std::string::npos);
  // The server goes on draining for a moment, then closes; the client may
  // keep sending meanwhile without harm.
  send_all(fd, std::string(65536, 'x'));
  ::close(fd);
  EXPECT_TRUE(c.source.commands().empty());
  const auto s = c.server.stats();
  EXPECT_EQ(count(Refusal::Unauthorised, s), 1U);
  EXPECT_EQ(s.commands_unauthorised, 1U);
  ASSERT_EQ(c.source.refusals().size(), 1U);
  EXPECT_EQ(c.source.refusals()[0], std::make_pair(Refusal::Unauthorised, 401));
}

TEST(ConsoleServerLimits, WithTheTokenABodyOverTheCapGets413UnreadAndOneUnderItIsServed) {
  HttpLimits l;
  l.max_body = 1024;
  Console c(l);
  const int fd = connect_to(c.port);
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(send_all(fd, "POST /api/command HTTP/1.1\r\nHost: t\r\nAuthorization: Bearer " + kToken +
                               "\r\nContent-Length: 1073741824\r\n\r\n{\"kind\":"));
  EXPECT_EQ(status_of(read_answer(fd)), 413);
  ::close(fd);
  std::string a;
  EXPECT_EQ(
      request(c.port, post_command("{\"kind\":\"pause\",\"pad\":\"" + std::string(1000, 'p') + "\"}", kToken), &a),
      413);
  EXPECT_EQ(request(c.port, post_command(R"({"kind":"pause"})", kToken), &a), 200) << a;
  // A body without a length (chunked) is not read either.
  EXPECT_EQ(request(c.port, "POST /api/command HTTP/1.1\r\nHost: t\r\nAuthorization: Bearer " + kToken +
                                "\r\nTransfer-Encoding: chunked\r\n\r\n10\r\n{\"kind\":\"pause\"}\r\n0\r\n\r\n"),
            411);
  ASSERT_EQ(c.source.commands().size(), 1U);
  EXPECT_EQ(c.source.commands()[0], (nlohmann::json{{"kind", "pause"}}));
  const auto s = c.server.stats();
  EXPECT_EQ(count(Refusal::BodyTooLarge, s), 2U);
  EXPECT_EQ(count(Refusal::LengthRequired, s), 1U);
}

TEST(ConsoleServerLimits,
     FiftySlowOrIdleConnectionsAndSixLongPollsFromOneClientLeaveEveryPollAndMetricsAndInfoAnswering) {
  HttpLimits l;  // the defaults: 8 workers, 4 long-polls per client
  Console c(l);
  std::vector<int> held;
  for (int i = 0; i < 25; ++i) held.push_back(connect_to(c.port));  // idle: connected, nothing sent
  for (int i = 0; i < 25; ++i) {                                    // slowloris: a head that never ends
    held.push_back(connect_to(c.port));
    send_all(held.back(), "GET /metrics HTTP/1.1\r\nHost: t\r\nX-Slow: ");
  }
  for (const int fd : held) ASSERT_GE(fd, 0);
  // Long-polls from the same client (six tabs of one browser): four are
  // held, the other two answered at once with the frame as it is - not
  // refused, so those tabs keep showing the swarm by polling.
  std::vector<int> polls;
  for (int i = 0; i < 6; ++i) {
    polls.push_back(connect_to(c.port));
    send_all(polls.back(), get("/api/frame?since=7&wait=1"));
  }
  ASSERT_TRUE(c.source.wait_for_waiting(4));
  int at_once = 0;
  std::vector<bool> answered(polls.size(), false);
  const auto until = std::chrono::steady_clock::now() + 10s;
  while (at_once < 2 && std::chrono::steady_clock::now() < until) {
    for (std::size_t i = 0; i < polls.size(); ++i) {
      pollfd p{polls[i], POLLIN, 0};
      if (answered[i] || ::poll(&p, 1, 10) <= 0) continue;
      answered[i] = true;
      const auto a = read_answer(polls[i]);
      EXPECT_EQ(status_of(a), 200) << a;
      EXPECT_NE(a.find("X-Pheromesh-Long-Poll: not-held"), std::string::npos) << a;
      EXPECT_NE(a.find("\"version\":7"), std::string::npos) << "the frame itself: " << a;
      ++at_once;
    }
  }
  EXPECT_EQ(at_once, 2);
  EXPECT_EQ(c.server.stats().long_polls_unheld, 2U);
  // Slow clients keep trickling while /metrics and /api/info are asked.
  for (int i = 25; i < 50; ++i) send_all(held[static_cast<std::size_t>(i)], "a");
  std::string a;
  EXPECT_EQ(request(c.port, get("/metrics"), &a), 200) << a;
  EXPECT_NE(a.find("pheromesh_tick 1"), std::string::npos);
  EXPECT_EQ(request(c.port, get("/api/info"), &a), 200) << a;
  EXPECT_GE(c.server.stats().open_connections, 50U + 4U);
  EXPECT_TRUE(c.source.refusals().empty()) << "a long-poll beyond the limit is no refusal";
  c.source.release();
  // Once released, the held four answer too, without the not-held mark.
  for (std::size_t i = 0; i < polls.size(); ++i) {
    if (answered[i]) continue;
    const auto a = read_answer(polls[i]);
    EXPECT_EQ(status_of(a), 200) << a;
    EXPECT_EQ(a.find("X-Pheromesh-Long-Poll"), std::string::npos) << a;
  }
  for (const int fd : polls) ::close(fd);
  for (const int fd : held) ::close(fd);
}

// The guard: cpp-httplib as the console used it before (one thread per
// connection, 8 by default) does not answer while 50 connections sit idle.
TEST(ConsoleServerLimits, GuardTheLibrarysOwnThreadPerConnectionStopsAnsweringUnderFiftyIdleConnections) {
  httplib::Server plain;
  plain.Get("/metrics", [](const httplib::Request&, httplib::Response& res) { res.set_content("ok", "text/plain"); });
  const int port = plain.bind_to_any_port("127.0.0.1");
  ASSERT_GT(port, 0);
  std::thread t([&plain] { plain.listen_after_bind(); });
  std::vector<int> idle;
  for (int i = 0; i < 50; ++i) idle.push_back(connect_to(static_cast<uint16_t>(port)));
  const int fd = connect_to(static_cast<uint16_t>(port));
  send_all(fd, get("/metrics"));
  const std::string a = read_answer(fd, 2s);  // shorter than its 5 s keep-alive wait
  EXPECT_EQ(status_of(a), 0) << "answered at once: the guard no longer shows what the poller is for";
  ::close(fd);
  for (const int i : idle) ::close(i);
  plain.stop();
  t.join();
}

TEST(ConsoleServerLimits, HeadersTooLargeOrTooSlowAreRefusedAndCounted) {
  HttpLimits l;
  l.max_head = 2048;
  l.head_timeout_s = 1;
  Console c(l);
  EXPECT_EQ(request(c.port, "GET /metrics HTTP/1.1\r\nHost: t\r\nX-Big: " + std::string(4096, 'b') + "\r\n\r\n"), 431);
  const int fd = connect_to(c.port);
  send_all(fd, "GET /metrics HTTP/1.1\r\nHost: t\r\n");
  EXPECT_EQ(status_of(read_answer(fd)), 408);
  ::close(fd);
  const auto s = c.server.stats();
  EXPECT_EQ(count(Refusal::HeadTooLarge, s), 1U);
  EXPECT_EQ(count(Refusal::HeadTimeout, s), 1U);
  EXPECT_EQ(request(c.port, get("/metrics")), 200);
}

TEST(ConsoleServerLimits, AtTheConnectionLimitTheLongestWaitingConnectionMakesRoom) {
  HttpLimits l;
  l.max_connections_per_client = 4;
  Console c(l);
  std::vector<int> idle;
  for (int i = 0; i < 4; ++i) {
    idle.push_back(connect_to(c.port));
    std::this_thread::sleep_for(20ms);  // an order among them: the first is the oldest
  }
  EXPECT_EQ(request(c.port, get("/metrics")), 200);
  // The oldest idle connection was closed for it.
  char b = 0;
  pollfd p{idle[0], POLLIN, 0};
  ASSERT_GT(::poll(&p, 1, 10000), 0);
  EXPECT_EQ(::recv(idle[0], &b, 1, 0), 0) << "closed by the server";
  EXPECT_GE(count(Refusal::TooManyConnections, c.server.stats()), 1U);
  for (const int fd : idle) ::close(fd);
}

TEST(ConsoleServerLimits, FrameQueriesWithNumbersThatDoNotFitAreRefusedNotWrapped) {
  Console c;
  std::string a;
  EXPECT_EQ(request(c.port, get("/api/frame?since=-1"), &a), 400) << a;
  EXPECT_EQ(request(c.port, get("/api/frame?since=18446744073709551616"), &a), 400) << a;
  EXPECT_EQ(request(c.port, get("/api/frame?layer=65536"), &a), 400) << a;
  EXPECT_EQ(request(c.port, get("/api/frame?layer=4294967296"), &a), 400) << a;
  EXPECT_EQ(request(c.port, get("/api/frame?t=nan"), &a), 400) << a;
  EXPECT_EQ(request(c.port, get("/api/frame?since=18446744073709551615&layer=3"), &a), 200) << a;
  EXPECT_NE(a.find("\"since\":18446744073709551615"), std::string::npos) << a;
  EXPECT_EQ(count(Refusal::BadRequest, c.server.stats()), 5U);
}

TEST(ConsoleServerLimits, KeepAliveRequestsOnOneConnectionAreAllServed) {
  Console c;
  const int fd = connect_to(c.port);
  ASSERT_TRUE(send_all(fd, get("/metrics") + get("/api/info")));  // pipelined
  std::string both;
  for (int i = 0; i < 100 && both.find("\"mode\":\"live\"") == std::string::npos; ++i) {
    const auto a = read_answer(fd, 100ms);
    both += a;
  }
  EXPECT_EQ(status_of(both), 200);
  EXPECT_NE(both.find("pheromesh_tick 1"), std::string::npos) << both;
  EXPECT_NE(both.find("\"mode\":\"live\""), std::string::npos) << both;
  ASSERT_TRUE(send_all(fd, post_command(R"({"kind":"resume"})", kToken)));
  EXPECT_EQ(status_of(read_answer(fd)), 200);
  ::close(fd);
  EXPECT_EQ(c.source.commands().size(), 1U);
}

}  // namespace
}  // namespace pheromesh::console
