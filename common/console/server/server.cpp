#include <httplib.h>

#include <array>
#include <atomic>
#include <map>
#include <mutex>

#include "guarded_server.hpp"
#include "pheromesh/auth/control.hpp"
#include "pheromesh/console/prometheus.hpp"
#include "pheromesh/console/request.hpp"
#include "pheromesh/console/server.hpp"
#include "pheromesh/web/assets.hpp"

namespace pheromesh::console {

struct ConsoleServer::Impl {
  ConsoleSource* source;
  ServerOptions opt;
  std::unique_ptr<detail::GuardedServer> http;
  std::thread thread;
  uint16_t port = 0;
  std::atomic<uint64_t> requests{0}, frame_requests{0}, body_bytes{0}, long_polls_unheld{0};
  std::array<std::atomic<uint64_t>, kRefusalKinds> refused{};
  // Long-polls held now, by client address and in all.
  std::mutex polls_mu;
  std::map<std::string, unsigned> polls_by_client;
  unsigned polls = 0;

  void refuse(Refusal reason, int status, const std::string& who, const std::string& what) {
    ++refused[static_cast<std::size_t>(reason)];
    source->refused(reason, status, who, what.substr(0, 200));  // a path may be 8 KiB long
  }
  bool take_poll(const std::string& client) {
    std::lock_guard lock(polls_mu);
    const unsigned mine = polls_by_client.count(client) ? polls_by_client[client] : 0;
    if (mine >= opt.limits.long_polls_per_client || polls >= max_polls()) return false;
    ++polls_by_client[client];
    ++polls;
    return true;
  }
  void give_poll(const std::string& client) {
    std::lock_guard lock(polls_mu);
    --polls;
    if (--polls_by_client[client] == 0) polls_by_client.erase(client);
  }
  // Long-polls may hold at most all workers but two, so that /metrics,
  // /api/info and commands always find one.
  [[nodiscard]] unsigned max_polls() const { return opt.limits.threads > 2 ? opt.limits.threads - 2 : 1; }

  // Every answer: counted, with its body's size.
  void count(const httplib::Response& res) {
    ++requests;
    body_bytes += res.body.size();
  }
  // Before the body is read: true if the request was refused on its head
  // (and answered).
  bool refuse_head(const httplib::Request& req, httplib::Response& res);
  // The routes of the console's API, /metrics and the web assets.
  void route(httplib::Server& http);
  void serve_frame(const httplib::Request& req, httplib::Response& res);
  void serve_command(const httplib::Request& req, httplib::Response& res);
  // Binds as the options ask: the port, or an error naming the address.
  core::Result<uint16_t> bind(httplib::Server& http);
};

namespace {
std::string dump(const nlohmann::json& j) { return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace); }

std::string who(const httplib::Request& req) { return "http " + req.remote_addr + ":" + std::to_string(req.remote_port); }

void answer_json(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(dump({{"ok", false}, {"message", message}}), "application/json");
}

std::optional<std::string_view> header(const httplib::Request& req, const char* name) {
  const auto it = req.headers.find(name);
  if (it == req.headers.end()) return std::nullopt;
  return std::string_view(it->second);
}

}  // namespace

std::string random_token() { return auth::random_hex(16); }

ConsoleServer::ConsoleServer(ConsoleSource& source, ServerOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->source = &source;
  impl_->opt = std::move(options);
}

ConsoleServer::~ConsoleServer() { stop(); }

// A request refused on its head (no token, a body too large or of unknown
// length, compressed) is answered at once, its body never read, and its
// connection closed after the answer.
bool ConsoleServer::Impl::refuse_head(const httplib::Request& req, httplib::Response& res) {
  const RequestHead head{req.method,
                         req.path,
                         header(req, "Content-Length"),
                         header(req, "Transfer-Encoding"),
                         header(req, "Content-Encoding"),
                         header(req, "Authorization")};
  const auto verdict = check_request_head(head, opt.token, opt.limits.max_body);
  if (!verdict) return false;
  answer_json(res, verdict->status, verdict->message);
  detail::GuardedServer::close_after_answer();
  // The library answers "Connection: close" when the request asked for it.
  const_cast<httplib::Request&>(req).set_header("Connection", "close");  // the server's own object, not const
  std::string what = req.method + " " + req.path;
  if (head.content_length) what += " (Content-Length " + std::string(*head.content_length).substr(0, 24) + ")";
  refuse(verdict->reason, verdict->status, who(req), what);
  count(res);
  return true;
}

void ConsoleServer::Impl::serve_frame(const httplib::Request& req, httplib::Response& res) {
  const auto q = parse_frame_query(req.params);
  if (!q) {
    answer_json(res, 400, q.error().message);
    refuse(Refusal::BadRequest, 400, who(req), "GET /api/frame: " + q.error().message);
    count(res);
    return;
  }
  // A long-poll beyond the limits is not refused but answered at once
  // with the frame as it is (no wait): the seventh tab of one browser
  // degrades to polling (the page waits 250 ms after an answer without
  // news that came back at once) instead of breaking, and a flood of
  // long-polls still holds no more workers than the limits allow.
  const bool held = q->wait && take_poll(req.remote_addr);
  if (q->wait && !held) {
    ++long_polls_unheld;
    res.set_header("X-Pheromesh-Long-Poll", "not-held");
  }
  try {
    res.set_content(dump(source->frame(q->layer, q->since, q->t, held)), "application/json");
  } catch (...) {
    if (held) give_poll(req.remote_addr);
    throw;
  }
  if (held) give_poll(req.remote_addr);
  res.set_header("Cache-Control", "no-store");
  ++frame_requests;
  count(res);
}

void ConsoleServer::Impl::serve_command(const httplib::Request& req, httplib::Response& res) {
  // The token was checked before the body was read (refuse_head).
  const auto body = parse_command_body(req.body);
  if (!body) {
    answer_json(res, 400, body.error().message);
  } else {
    const auto a = source->command(body.value(), who(req));
    res.status = a.status;
    res.set_content(dump({{"ok", a.status == 200}, {"message", a.message}}), "application/json");
  }
  count(res);
}

void ConsoleServer::Impl::route(httplib::Server& http) {
  // gzip, never brotli: the packaged cpp-httplib compresses brotli at quality
  // 11, which took 8.7 s for one 47 KB frame on a loaded 2-core host (gzip:
  // 0.3 s) and held the browser's updates below 1 per second. The library
  // picks brotli whenever "br" appears in Accept-Encoding, so it is taken out.
  http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    if (refuse_head(req, res)) return httplib::Server::HandlerResponse::Handled;
    auto& headers = const_cast<httplib::Request&>(req).headers;  // the server's own object, not const
    auto [first, last] = headers.equal_range("Accept-Encoding");
    for (auto it = first; it != last; ++it) {
      for (auto p = it->second.find("br"); p != std::string::npos; p = it->second.find("br")) it->second.erase(p, 2);
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  // A client that asks before sending its body ("Expect: 100-continue", as
  // curl does for large bodies) gets the refusal instead of "continue".
  http.set_expect_100_continue_handler(
      [this](const httplib::Request& req, httplib::Response& res) { return refuse_head(req, res) ? res.status : 100; });
  http.Get("/api/info", [this](const httplib::Request&, httplib::Response& res) {
    res.set_content(dump(source->info()), "application/json");
    res.set_header("Cache-Control", "no-store");
    count(res);
  });
  http.Get("/api/frame", [this](const httplib::Request& req, httplib::Response& res) { serve_frame(req, res); });
  http.Post("/api/command", [this](const httplib::Request& req, httplib::Response& res) { serve_command(req, res); });
  http.Get("/metrics", [this](const httplib::Request&, httplib::Response& res) {
    res.set_content(source->metrics(), kExpositionContentType);
    count(res);
  });
  http.Get(R"(/.*)", [this](const httplib::Request& req, httplib::Response& res) {
    const web::Asset* a = web::find_asset(req.path);
    if (a == nullptr) {
      res.status = 404;
      res.set_content("not found\n", "text/plain");
    } else {
      res.set_content(std::string(a->body), std::string(a->content_type));
    }
    count(res);
  });
}

core::Result<uint16_t> ConsoleServer::Impl::bind(httplib::Server& http) {
  // SO_REUSEADDR only: the library's default also sets SO_REUSEPORT, with
  // which a second console binds a port already in use and the two share
  // its connections. A taken port must be an error.
  http.set_socket_options([](int sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  const int bound =
      opt.port == 0 ? http.bind_to_any_port(opt.bind) : (http.bind_to_port(opt.bind, opt.port) ? opt.port : -1);
  if (bound <= 0) {
    return core::Error{"cannot listen on " + opt.bind + ":" + std::to_string(opt.port) +
                       " (in use, or not an address of this host)"};
  }
  return static_cast<uint16_t>(bound);
}

core::Result<uint16_t> ConsoleServer::start() {
  Impl& m = *impl_;
  m.http = std::make_unique<detail::GuardedServer>(
      m.opt.limits, [&m](Refusal reason, int status, const std::string& who, const std::string& what) {
        m.refuse(reason, status, who, what);
      });
  m.route(*m.http);
  auto port = m.bind(*m.http);
  if (!port) return port;
  m.port = port.value();
  m.http->start_workers();
  m.thread = std::thread([&http = *m.http] { http.listen_after_bind(); });
  return m.port;
}

void ConsoleServer::stop() {
  if (!impl_ || !impl_->http) return;
  impl_->http->stop();
  if (impl_->thread.joinable()) impl_->thread.join();
  impl_->http->stop_workers();
}

ServerStats ConsoleServer::stats() const {
  ServerStats s;
  s.requests = impl_->requests.load();
  s.frame_requests = impl_->frame_requests.load();
  s.body_bytes = impl_->body_bytes.load();
  for (std::size_t i = 0; i < kRefusalKinds; ++i) s.refused[i] = impl_->refused[i].load();
  s.commands_unauthorised = s.refused[static_cast<std::size_t>(Refusal::Unauthorised)];
  s.open_connections = impl_->http ? impl_->http->open_connections() : 0;
  s.long_polls_unheld = impl_->long_polls_unheld.load();
  return s;
}

std::string ConsoleServer::url() const {
  const std::string host = impl_->opt.bind == "0.0.0.0" ? "127.0.0.1" : impl_->opt.bind;
  return "http://" + host + ":" + std::to_string(impl_->port) + "/" +
         (impl_->opt.token.empty() ? "" : "?token=" + impl_->opt.token);
}

}  // namespace pheromesh::console
