// cpp-httplib's request parsing and routing, with connections handled so
// that slow or idle clients cannot take the console away from others.
//
// The library gives each connection one thread for its whole life (8
// threads by default), so eight clients that send their headers one byte at
// a time, or hold keep-alive connections open, leave nothing for anyone
// else. Here one poller thread holds every connection that is waiting for
// a request (connecting, between keep-alive requests, sending its headers
// slowly) and hands a connection to a bounded pool of workers only once its
// request line and headers are complete. A worker then runs the library's
// process_request() on them (and reads the body, if the head was accepted)
// and hands the connection back. Slow clients cost a file descriptor and a
// slot in poll(), not a thread, and are closed when their headers are not
// complete in time. The limits are HttpLimits (console/request.hpp).
#pragma once

#include <httplib.h>

#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "pheromesh/console/request.hpp"

namespace pheromesh::console::detail {

class GuardedServer final : public httplib::Server {
 public:
  // Told of refusals made before a request reaches a handler (headers too
  // large or too slow, connection limits), from the poller thread.
  using RefusalHook = std::function<void(Refusal, int status, const std::string& who, const std::string& what)>;

  GuardedServer(HttpLimits limits, RefusalHook hook);
  ~GuardedServer() override;
  GuardedServer(const GuardedServer&) = delete;
  GuardedServer& operator=(const GuardedServer&) = delete;

  // The poller and the workers; after binding, before listen_after_bind().
  // Also lengthens the listen backlog: the library's is 5, so a burst of
  // connections (a client opening many, a browser reconnecting) overflows it
  // and the kernel drops new connections' SYNs, which clients retry only
  // after a second, before the accepting thread can take them.
  void start_workers();
  // After Server::stop() and the end of listen_after_bind(): answers in
  // progress finish, every connection is closed.
  void stop_workers();

  // Called by a handler (or the pre-routing check) on the worker's thread:
  // close the connection after this answer, since the request's body was
  // not read and what follows on the connection is not a request.
  static void close_after_answer();

  [[nodiscard]] unsigned open_connections() const;

 private:
  struct Conn;
  using ConnPtr = std::unique_ptr<Conn>;

  bool process_and_close_socket(socket_t sock) override;  // on the accepting thread: hand over to the poller
  void poll_loop();
  void work_loop();
  void serve(ConnPtr c);
  void hand_back(ConnPtr c);
  bool admit(Conn& c);
  void take_inbox();
  void close_conn(ConnPtr c);
  void start_draining(ConnPtr c);
  void wake();

  HttpLimits limits_;
  RefusalHook hook_;
  int wake_fd_ = -1;
  bool stopping_ = false;  // under inbox_mu_
  std::thread poller_;
  std::vector<std::thread> workers_;

  std::mutex inbox_mu_;
  std::deque<ConnPtr> inbox_;  // accepted, or back from a worker
  std::mutex ready_mu_;
  std::condition_variable ready_cv_;
  std::deque<ConnPtr> ready_;  // complete heads, for the workers
  bool ready_stop_ = false;
  std::vector<ConnPtr> waiting_;  // the poller's own

  mutable std::mutex count_mu_;
  unsigned open_ = 0;
  std::map<std::string, unsigned> open_by_client_;
};

}  // namespace pheromesh::console::detail
