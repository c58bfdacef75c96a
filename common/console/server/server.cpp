#include <httplib.h>

#include <atomic>
#include <fstream>
#include <mutex>

#include "pheromesh/auth/control.hpp"
#include "pheromesh/console/server.hpp"
#include "pheromesh/console/prometheus.hpp"
#include "pheromesh/web/assets.hpp"

namespace pheromesh::console {

struct ConsoleServer::Impl {
  ConsoleSource* source;
  ServerOptions opt;
  httplib::Server http;
  std::thread thread;
  uint16_t port = 0;
  std::atomic<uint64_t> requests{0}, frame_requests{0}, body_bytes{0}, unauthorised{0};
};

namespace {
std::string dump(const nlohmann::json& j) { return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace); }

bool same_token(const std::string& a, const std::string& b) {
  // Constant time in the token's length.
  if (a.size() != b.size() || a.empty()) return false;
  unsigned char d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d |= static_cast<unsigned char>(a[i] ^ b[i]);
  return d == 0;
}
}  // namespace

std::string random_token() { return auth::random_hex(16); }

ConsoleServer::ConsoleServer(ConsoleSource& source, ServerOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->source = &source;
  impl_->opt = std::move(options);
}

ConsoleServer::~ConsoleServer() { stop(); }

core::Result<uint16_t> ConsoleServer::start() {
  Impl& m = *impl_;
  auto& http = m.http;
  const auto count = [&m](httplib::Response& res) {
    ++m.requests;
    m.body_bytes += res.body.size();
  };
  // gzip, never brotli: the packaged cpp-httplib compresses brotli at quality
  // 11, which took 8.7 s for one 47 KB frame on a loaded 2-core host (gzip:
  // 0.3 s) and held the browser's updates below 1 per second. The library
  // picks brotli whenever "br" appears in Accept-Encoding, so it is taken out.
  http.set_pre_routing_handler([](const httplib::Request& req, httplib::Response&) {
    auto& headers = const_cast<httplib::Request&>(req).headers;  // the server's own object, not const
    auto [first, last] = headers.equal_range("Accept-Encoding");
    for (auto it = first; it != last; ++it) {
      for (auto p = it->second.find("br"); p != std::string::npos; p = it->second.find("br")) it->second.erase(p, 2);
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  http.Get("/api/info", [&m, count](const httplib::Request&, httplib::Response& res) {
    res.set_content(dump(m.source->info()), "application/json");
    res.set_header("Cache-Control", "no-store");
    count(res);
  });
  http.Get("/api/frame", [&m, count](const httplib::Request& req, httplib::Response& res) {
    uint64_t since = 0;
    long layer = 0;
    std::optional<double> t;
    try {
      if (req.has_param("since")) since = std::stoull(req.get_param_value("since"));
      if (req.has_param("layer")) layer = std::stol(req.get_param_value("layer"));
      if (req.has_param("t")) t = std::stod(req.get_param_value("t"));
    } catch (const std::exception&) {
      res.status = 400;
      res.set_content(R"({"ok":false,"message":"since, layer and t must be numbers"})", "application/json");
      count(res);
      return;
    }
    if (layer < 0 || layer > 65535) {
      res.status = 400;
      res.set_content(R"({"ok":false,"message":"layer out of range"})", "application/json");
      count(res);
      return;
    }
    const bool wait = req.has_param("wait") && req.get_param_value("wait") == "1";
    res.set_content(dump(m.source->frame(static_cast<uint16_t>(layer), since, t, wait)), "application/json");
    res.set_header("Cache-Control", "no-store");
    ++m.frame_requests;
    count(res);
  });
  http.Post("/api/command", [&m, count](const httplib::Request& req, httplib::Response& res) {
    const std::string who = "http " + req.remote_addr + ":" + std::to_string(req.remote_port);
    std::string token;
    const std::string auth = req.get_header_value("Authorization");
    if (auth.rfind("Bearer ", 0) == 0) token = auth.substr(7);
    nlohmann::json answer;
    if (!same_token(token, m.opt.token)) {
      ++m.unauthorised;
      res.status = 401;
      answer = {{"ok", false}, {"message", m.opt.token.empty() ? "this console takes no commands"
                                                               : "missing or wrong token (use the URL the ground station printed)"}};
      // Logged by the source too, so an operator sees refused attempts.
      m.source->command(nlohmann::json{{"kind", "unauthorised"}, {"body", req.body.substr(0, 200)}}, who);
    } else {
      nlohmann::json body = nlohmann::json::parse(req.body, nullptr, false);
      if (body.is_discarded() || !body.is_object()) {
        res.status = 400;
        answer = {{"ok", false}, {"message", "the body must be a JSON object, e.g. {\"kind\":\"pause\"}"}};
      } else {
        const auto a = m.source->command(body, who);
        res.status = a.status;
        answer = {{"ok", a.status == 200}, {"message", a.message}};
      }
    }
    res.set_content(dump(answer), "application/json");
    count(res);
  });
  http.Get("/metrics", [&m, count](const httplib::Request&, httplib::Response& res) {
    res.set_content(m.source->metrics(), kExpositionContentType);
    count(res);
  });
  http.Get(R"(/.*)", [count](const httplib::Request& req, httplib::Response& res) {
    const web::Asset* a = web::find_asset(req.path);
    if (a == nullptr) {
      res.status = 404;
      res.set_content("not found\n", "text/plain");
    } else {
      res.set_content(std::string(a->body), std::string(a->content_type));
    }
    count(res);
  });
  // SO_REUSEADDR only: the library's default also sets SO_REUSEPORT, with
  // which a second console binds a port already in use and the two share
  // its connections. A taken port must be an error.
  http.set_socket_options([](int sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  const int port = m.opt.port == 0 ? http.bind_to_any_port(m.opt.bind) : (http.bind_to_port(m.opt.bind, m.opt.port) ? m.opt.port : -1);
  if (port <= 0) {
    return core::Error{"cannot listen on " + m.opt.bind + ":" + std::to_string(m.opt.port) +
                       " (in use, or not an address of this host)"};
  }
  m.port = static_cast<uint16_t>(port);
  m.thread = std::thread([&http] { http.listen_after_bind(); });
  return m.port;
}

void ConsoleServer::stop() {
  if (!impl_) return;
  impl_->http.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

ServerStats ConsoleServer::stats() const {
  return {impl_->requests.load(), impl_->frame_requests.load(), impl_->body_bytes.load(), impl_->unauthorised.load()};
}

std::string ConsoleServer::url() const {
  const std::string host = impl_->opt.bind == "0.0.0.0" ? "127.0.0.1" : impl_->opt.bind;
  return "http://" + host + ":" + std::to_string(impl_->port) + "/" +
         (impl_->opt.token.empty() ? "" : "?token=" + impl_->opt.token);
}

}  // namespace pheromesh::console
