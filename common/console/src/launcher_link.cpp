#include "pheromesh/console/launcher_link.hpp"

#include <poll.h>
#include <sys/socket.h>

namespace pheromesh::console {

ConsoleSource::Answer LauncherLink::ask(const std::string& request) const {
  if (fd_ < 0) return {409, "kill and restart need the launcher: start the swarm with pheromesh run"};
  const std::string out = request + "\n";
  if (::send(fd_, out.data(), out.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(out.size())) {
    return {409, "the launcher is gone"};
  }
  std::string reply;
  const auto deadline = std::chrono::steady_clock::now() + timeout_;
  while (reply.empty() || reply.back() != '\n') {
    pollfd p{fd_, POLLIN, 0};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0 || ::poll(&p, 1, static_cast<int>(left)) <= 0) {
      return {504, "the launcher did not answer within " + std::to_string(timeout_.count()) + " ms"};
    }
    char buf[512];
    const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
    if (n <= 0) return {409, "the launcher is gone"};
    reply.append(buf, static_cast<std::size_t>(n));
  }
  reply.pop_back();
  if (reply.rfind("ok ", 0) == 0) return {200, reply.substr(3)};
  return {409, reply.rfind("error ", 0) == 0 ? reply.substr(6) : reply};
}

}  // namespace pheromesh::console
