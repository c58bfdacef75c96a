#include "guarded_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>

namespace pheromesh::console::detail {

using Clock = std::chrono::steady_clock;

namespace {
thread_local bool t_close_after_answer = false;

Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

int ms_until(Clock::time_point deadline, Clock::time_point now) {
  if (deadline <= now) return 0;
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now).count() + 1;
  return static_cast<int>(std::min<int64_t>(ms, 1000));
}

void address(const sockaddr_storage& a, std::string& ip, int& port) {
  char buf[INET6_ADDRSTRLEN] = {};
  if (a.ss_family == AF_INET) {
    const auto& v4 = reinterpret_cast<const sockaddr_in&>(a);
    inet_ntop(AF_INET, &v4.sin_addr, buf, sizeof buf);
    port = ntohs(v4.sin_port);
  } else if (a.ss_family == AF_INET6) {
    const auto& v6 = reinterpret_cast<const sockaddr_in6&>(a);
    inet_ntop(AF_INET6, &v6.sin6_addr, buf, sizeof buf);
    port = ntohs(v6.sin6_port);
  }
  ip = buf;
}

// Best effort, never blocking: a short answer to a connection about to be
// closed (its client may not be reading).
void send_now(int fd, const std::string& s) { (void)::send(fd, s.data(), s.size(), MSG_NOSIGNAL | MSG_DONTWAIT); }

std::string short_answer(int status, const char* reason, const std::string& message) {
  const std::string body = R"({"ok":false,"message":")" + message + "\"}";
  return "HTTP/1.1 " + std::to_string(status) + " " + reason +
         "\r\nContent-Type: application/json\r\nConnection: close\r\nContent-Length: " + std::to_string(body.size()) +
         "\r\n\r\n" + body;
}
}  // namespace

struct GuardedServer::Conn {
  int fd = -1;
  std::string ip, local_ip;
  int port = 0, local_port = 0;
  std::string buf;  // received, not yet consumed
  Clock::time_point deadline;
  bool fresh = true;      // not yet admitted (counted)
  bool draining = false;  // answered and half-closed: reading what the client still sends, then closing
  std::size_t drained = 0;
  unsigned served = 0;  // requests answered on this connection
  [[nodiscard]] std::string who() const { return "http " + ip + ":" + std::to_string(port); }
};

namespace {
// The library's Stream over one connection: first the bytes the poller
// already received (the request's head), then the socket, each wait
// bounded by the read or write timeout and the whole request by a deadline.
class ConnStream final : public httplib::Stream {
 public:
  ConnStream(int fd, std::string& buf, const std::string& ip, int port, const std::string& local_ip, int local_port,
             const HttpLimits& l)
      : fd_(fd),
        buf_(buf),
        ip_(ip),
        local_ip_(local_ip),
        port_(port),
        local_port_(local_port),
        limits_(l),
        deadline_(Clock::now() + seconds(2 * (l.read_timeout_s + l.write_timeout_s))),
        socket_budget_(l.max_body + 1) {}

  bool is_readable() const override { return pos_ < buf_.size() || wait_for(POLLIN, limits_.read_timeout_s); }
  bool is_writable() const override { return wait_for(POLLOUT, limits_.write_timeout_s); }

  ssize_t read(char* ptr, size_t size) override {
    if (pos_ < buf_.size()) {
      const std::size_t n = std::min(size, buf_.size() - pos_);
      std::memcpy(ptr, buf_.data() + pos_, n);
      pos_ += n;
      return static_cast<ssize_t>(n);
    }
    // The head was checked before this: what is read from the socket now is
    // a body of at most max_body bytes. More is not a request we accept.
    if (socket_budget_ == 0) return -1;
    if (!wait_for(POLLIN, limits_.read_timeout_s)) return -1;
    const ssize_t n = ::recv(fd_, ptr, std::min(size, socket_budget_), MSG_DONTWAIT);
    if (n > 0) socket_budget_ -= static_cast<std::size_t>(n);
    return n;
  }

  ssize_t write(const char* ptr, size_t size) override {
    std::size_t sent = 0;
    while (sent < size) {
      const ssize_t n = ::send(fd_, ptr + sent, size - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
      if (n > 0) {
        sent += static_cast<std::size_t>(n);
      } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
        if (!wait_for(POLLOUT, limits_.write_timeout_s)) return -1;
      } else {
        return -1;
      }
    }
    return static_cast<ssize_t>(size);
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = ip_;
    port = port_;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = local_ip_;
    port = local_port_;
  }
  socket_t socket() const override { return fd_; }

  // What the client sent after this request (a pipelined next request).
  void keep_rest() { buf_.erase(0, pos_); }

 private:
  bool wait_for(short events, double timeout_s) const {
    const auto now = Clock::now();
    const auto until = std::min(deadline_, now + seconds(timeout_s));
    for (;;) {
      pollfd p{fd_, events, 0};
      const auto left = until - Clock::now();
      const int ms =
          static_cast<int>(std::max<int64_t>(0, std::chrono::duration_cast<std::chrono::milliseconds>(left).count()));
      const int r = ::poll(&p, 1, ms);
      if (r > 0) return true;
      if (r == 0 || errno != EINTR) return false;
    }
  }

  int fd_;
  std::string& buf_;
  std::size_t pos_ = 0;
  const std::string &ip_, &local_ip_;
  int port_, local_port_;
  const HttpLimits& limits_;
  Clock::time_point deadline_;
  std::size_t socket_budget_;
};

// Runs what the library's accepting loop hands over at once, on that
// thread: GuardedServer::process_and_close_socket only passes the socket on.
class InlineQueue final : public httplib::TaskQueue {
 public:
  void enqueue(std::function<void()> fn) override { fn(); }
  void shutdown() override {}
};
}  // namespace

GuardedServer::GuardedServer(HttpLimits limits, RefusalHook hook) : limits_(limits), hook_(std::move(hook)) {
  limits_.threads = std::max(1U, limits_.threads);
  new_task_queue = [] { return new InlineQueue; };
  // The library's own cap, should a body ever be read past the head check.
  set_payload_max_length(limits_.max_body);
  set_keep_alive_max_count(limits_.max_requests_per_connection);
  set_keep_alive_timeout(static_cast<time_t>(limits_.idle_timeout_s));
}

GuardedServer::~GuardedServer() { stop_workers(); }

void GuardedServer::close_after_answer() { t_close_after_answer = true; }

unsigned GuardedServer::open_connections() const {
  std::lock_guard lock(count_mu_);
  return open_;
}

void GuardedServer::start_workers() {
  // listen() again on a listening socket only sets its backlog (Linux).
  const socket_t listening = svr_sock_;
  if (listening != INVALID_SOCKET) (void)::listen(listening, static_cast<int>(limits_.max_connections));
  wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  poller_ = std::thread([this] { poll_loop(); });
  for (unsigned i = 0; i < limits_.threads; ++i) workers_.emplace_back([this] { work_loop(); });
}

void GuardedServer::stop_workers() {
  if (!poller_.joinable()) return;
  {
    std::lock_guard lock(inbox_mu_);
    stopping_ = true;
  }
  wake();
  poller_.join();
  {
    std::lock_guard lock(ready_mu_);
    ready_stop_ = true;
  }
  ready_cv_.notify_all();
  for (auto& w : workers_) w.join();
  workers_.clear();
  // Nothing runs now: close whatever is left.
  for (auto& c : waiting_) close_conn(std::move(c));
  waiting_.clear();
  for (auto& c : inbox_) close_conn(std::move(c));
  inbox_.clear();
  for (auto& c : ready_) close_conn(std::move(c));
  ready_.clear();
  ::close(wake_fd_);
  wake_fd_ = -1;
}

void GuardedServer::wake() {
  const uint64_t one = 1;
  (void)!::write(wake_fd_, &one, sizeof one);
}

bool GuardedServer::process_and_close_socket(socket_t sock) {
  auto c = std::make_unique<Conn>();
  c->fd = sock;
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  if (::getpeername(sock, reinterpret_cast<sockaddr*>(&a), &len) == 0) address(a, c->ip, c->port);
  len = sizeof a;
  if (::getsockname(sock, reinterpret_cast<sockaddr*>(&a), &len) == 0) address(a, c->local_ip, c->local_port);
  c->deadline = Clock::now() + seconds(limits_.head_timeout_s);
  {
    std::lock_guard lock(inbox_mu_);
    if (stopping_) {
      ::close(sock);
      return false;
    }
    inbox_.push_back(std::move(c));
  }
  wake();
  return true;
}

void GuardedServer::close_conn(ConnPtr c) {
  if (!c) return;
  ::close(c->fd);
  if (c->fresh) return;  // never counted
  std::lock_guard lock(count_mu_);
  --open_;
  auto it = open_by_client_.find(c->ip);
  if (it != open_by_client_.end() && --it->second == 0) open_by_client_.erase(it);
}

// A new connection within the limits, making room if it can: at a limit, the
// connection of that client (or of anyone, for the total) that has waited
// longest for a request is closed, since slow and idle connections are what
// fills the limits; a new one is refused only when every open connection
// is being answered.
bool GuardedServer::admit(Conn& c) {
  for (int attempt = 0; attempt < 2; ++attempt) {
    bool client_full = false;
    {
      std::lock_guard lock(count_mu_);
      const unsigned mine = open_by_client_.count(c.ip) ? open_by_client_[c.ip] : 0;
      client_full = mine >= limits_.max_connections_per_client;
      if (!client_full && open_ < limits_.max_connections) {
        ++open_;
        ++open_by_client_[c.ip];
        c.fresh = false;
        return true;
      }
    }
    if (attempt == 1) break;
    auto victim = waiting_.end();
    for (auto it = waiting_.begin(); it != waiting_.end(); ++it) {
      if ((*it)->draining || (client_full && (*it)->ip != c.ip)) continue;
      if (victim == waiting_.end() || (*it)->deadline < (*victim)->deadline) victim = it;
    }
    if (victim == waiting_.end()) break;
    ConnPtr v = std::move(*victim);
    waiting_.erase(victim);
    hook_(Refusal::TooManyConnections, 0, v->who(), "connection closed to make room for a new one");
    close_conn(std::move(v));
  }
  send_now(c.fd, short_answer(503, "Service Unavailable", "too many connections"));
  hook_(Refusal::TooManyConnections, 503, c.who(), "new connection refused");
  return false;
}

void GuardedServer::take_inbox() {
  std::deque<ConnPtr> in;
  {
    std::lock_guard lock(inbox_mu_);
    in.swap(inbox_);
  }
  for (auto& c : in) {
    if (c->fresh && !admit(*c)) {
      close_conn(std::move(c));
      continue;
    }
    if (!c->draining && c->buf.find("\r\n\r\n") != std::string::npos) {
      {
        std::lock_guard lock(ready_mu_);
        ready_.push_back(std::move(c));
      }
      ready_cv_.notify_one();
    } else {
      waiting_.push_back(std::move(c));
    }
  }
}

void GuardedServer::poll_loop() {
  std::vector<pollfd> fds;
  char tmp[16 * 1024];
  for (;;) {
    {
      std::lock_guard lock(inbox_mu_);
      if (stopping_) return;
    }
    take_inbox();
    auto now = Clock::now();
    // Deadlines: a head that did not arrive in time, an idle keep-alive
    // connection, a half-closed connection drained long enough.
    for (auto& c : waiting_) {
      if (c->deadline > now) continue;
      if (!c->draining && !c->buf.empty()) {
        // A connection that sent nothing is closed quietly: browsers open
        // spare connections they may never use.
        hook_(Refusal::HeadTimeout, 408, c->who(), "request headers not complete in time");
        send_now(c->fd, short_answer(408, "Request Timeout", "request headers not complete in time"));
      }
      close_conn(std::move(c));
    }
    std::erase(waiting_, nullptr);
    fds.assign(1, pollfd{wake_fd_, POLLIN, 0});
    int timeout_ms = 1000;
    for (const auto& c : waiting_) {
      fds.push_back({c->fd, POLLIN, 0});
      timeout_ms = std::min(timeout_ms, ms_until(c->deadline, now));
    }
    const int r = ::poll(fds.data(), fds.size(), timeout_ms);
    if (r < 0 && errno != EINTR) return;
    if (r <= 0) continue;
    if (fds[0].revents != 0) {
      uint64_t n = 0;
      (void)!::read(wake_fd_, &n, sizeof n);
    }
    now = Clock::now();
    for (std::size_t i = 1; i < fds.size(); ++i) {
      if (fds[i].revents == 0) continue;
      ConnPtr& c = waiting_[i - 1];
      const ssize_t n = ::recv(c->fd, tmp, sizeof tmp, MSG_DONTWAIT);
      if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) continue;
      if (n <= 0) {  // closed by the client, or an error
        close_conn(std::move(c));
        continue;
      }
      if (c->draining) {
        c->drained += static_cast<std::size_t>(n);
        if (c->drained > 1024 * 1024) close_conn(std::move(c));
        continue;
      }
      if (c->buf.empty() && c->served > 0)
        c->deadline = now + seconds(limits_.head_timeout_s);  // a keep-alive request begins
      const std::size_t from = c->buf.size() < 3 ? 0 : c->buf.size() - 3;
      c->buf.append(tmp, static_cast<std::size_t>(n));
      const std::size_t end = c->buf.find("\r\n\r\n", from);
      if ((end == std::string::npos && c->buf.size() > limits_.max_head) ||
          (end != std::string::npos && end + 4 > limits_.max_head)) {
        hook_(Refusal::HeadTooLarge, 431, c->who(),
              "request line and headers above " + std::to_string(limits_.max_head) + " bytes");
        send_now(c->fd, short_answer(431, "Request Header Fields Too Large", "request line and headers too large"));
        c->buf.clear();
        ::shutdown(c->fd, SHUT_WR);
        c->draining = true;
        c->deadline = now + std::chrono::seconds(2);
        continue;
      }
      if (end == std::string::npos) continue;
      {
        std::lock_guard lock(ready_mu_);
        ready_.push_back(std::move(c));
      }
      ready_cv_.notify_one();
    }
    std::erase(waiting_, nullptr);
  }
}

void GuardedServer::work_loop() {
  for (;;) {
    ConnPtr c;
    {
      std::unique_lock lock(ready_mu_);
      ready_cv_.wait(lock, [this] { return ready_stop_ || !ready_.empty(); });
      if (ready_stop_) return;
      c = std::move(ready_.front());
      ready_.pop_front();
    }
    serve(std::move(c));
  }
}

void GuardedServer::serve(ConnPtr c) {
  t_close_after_answer = false;
  const bool last = ++c->served >= limits_.max_requests_per_connection;
  bool client_closes = false;
  ConnStream s(c->fd, c->buf, c->ip, c->port, c->local_ip, c->local_port, limits_);
  const bool written = process_request(s, last, client_closes, nullptr);
  s.keep_rest();
  if (t_close_after_answer && written) {
    start_draining(std::move(c));
  } else if (!written || last || client_closes || t_close_after_answer) {
    close_conn(std::move(c));
  } else {
    c->deadline = Clock::now() + seconds(c->buf.empty() ? limits_.idle_timeout_s : limits_.head_timeout_s);
    hand_back(std::move(c));
  }
}

// The answer is sent, the body was not read: stop sending and read (and
// drop) what the client still sends for a moment, so that closing does not
// reset the connection before the client has read the answer.
void GuardedServer::start_draining(ConnPtr c) {
  ::shutdown(c->fd, SHUT_WR);
  c->buf.clear();
  c->draining = true;
  c->deadline = Clock::now() + std::chrono::seconds(2);
  hand_back(std::move(c));
}

void GuardedServer::hand_back(ConnPtr c) {
  {
    std::lock_guard lock(inbox_mu_);
    if (!stopping_) {
      inbox_.push_back(std::move(c));
    }
  }
  if (c) {
    close_conn(std::move(c));
    return;
  }
  wake();
}

}  // namespace pheromesh::console::detail
