#include "mavlink_link.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <memory>

namespace pheromesh::groundstation {

core::Result<std::unique_ptr<MavlinkLink>> MavlinkLink::open(const console::MavlinkTarget& target) {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* res = nullptr;
  const std::string port = std::to_string(target.port);
  if (const int rc = getaddrinfo(target.host.c_str(), port.c_str(), &hints, &res); rc != 0 || res == nullptr) {
    return core::Error{"--mavlink udp:" + target.host + ":" + port + ": cannot resolve " + target.host + ": " +
                       gai_strerror(rc)};
  }
  sockaddr_in to{};
  std::memcpy(&to, res->ai_addr, sizeof to);
  freeaddrinfo(res);
  const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return core::Error{std::string("--mavlink: cannot open a UDP socket: ") + std::strerror(errno)};
  // An ephemeral port on every interface: a station answers to where the frames came from.
  sockaddr_in any{};
  any.sin_family = AF_INET;
  any.sin_addr.s_addr = htonl(INADDR_ANY);
  if (bind(fd, reinterpret_cast<const sockaddr*>(&any), sizeof any) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd);
    return core::Error{"--mavlink: cannot bind a UDP socket: " + why};
  }
  char ip[INET_ADDRSTRLEN] = {};
  inet_ntop(AF_INET, &to.sin_addr, ip, sizeof ip);
  return std::unique_ptr<MavlinkLink>(new MavlinkLink(fd, to, std::string(ip) + ":" + port));
}

MavlinkLink::~MavlinkLink() { ::close(fd_); }

bool MavlinkLink::send(std::span<const uint8_t> bytes) { return reply(to_, bytes); }

bool MavlinkLink::reply(const sockaddr_in& to, std::span<const uint8_t> bytes) {
  const ssize_t n = ::sendto(fd_, bytes.data(), bytes.size(), MSG_DONTWAIT | MSG_NOSIGNAL,
                             reinterpret_cast<const sockaddr*>(&to), sizeof to);
  if (n == static_cast<ssize_t>(bytes.size())) return true;
  ++dropped_;  // EAGAIN (the socket's buffer is full), ECONNREFUSED (nobody listens yet), ...
  return false;
}

std::vector<MavlinkLink::Datagram> MavlinkLink::receive(std::size_t max) {
  std::vector<Datagram> out;
  while (out.size() < max) {
    Datagram d;
    socklen_t len = sizeof d.from;
    const ssize_t n =
        ::recvfrom(fd_, buf_.data(), buf_.size(), MSG_DONTWAIT, reinterpret_cast<sockaddr*>(&d.from), &len);
    if (n < 0) {
      if (errno == EINTR) continue;
      break;  // EAGAIN: nothing more; ECONNREFUSED from an earlier send: try again next time
    }
    d.bytes.assign(buf_.begin(), buf_.begin() + n);
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace pheromesh::groundstation
