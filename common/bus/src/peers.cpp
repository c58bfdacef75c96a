#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <cctype>
#include <memory>

#include "pheromesh/bus/bus.hpp"

namespace pheromesh::bus {
namespace {

std::string trim(const std::string& s) {
  std::size_t a = 0;
  std::size_t b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a])) != 0) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1])) != 0) --b;
  return s.substr(a, b - a);
}

// RFC 1123 host name: labels of letters, digits and '-', dots between.
bool is_host_name(const std::string& s) {
  if (s.empty() || s.size() > 253 || s.front() == '.' || s.front() == '-') return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '.'; });
}

}  // namespace

core::Result<ResolvedPeers> resolve_peers(const std::string& list) {
  ResolvedPeers out;
  auto add = [&](const std::string& a) {
    if (std::find(out.addresses.begin(), out.addresses.end(), a) == out.addresses.end()) out.addresses.push_back(a);
  };
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = list.find(',', start);
    const std::string item = trim(list.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (!item.empty()) {
      in_addr numeric{};
      if (inet_pton(AF_INET, item.c_str(), &numeric) == 1) {
        add(item);
      } else if (!is_host_name(item)) {
        return core::Error{"DDS peer '" + item +
                           "' is neither an IPv4 address nor a host name (expected e.g. 10.0.0.2 or "
                           "uav-host-1, comma-separated, no ports)"};
      } else {
        addrinfo hints{};
        hints.ai_family = AF_INET;
        hints.ai_socktype = SOCK_DGRAM;
        addrinfo* res = nullptr;
        if (getaddrinfo(item.c_str(), nullptr, &hints, &res) != 0 || res == nullptr) {
          out.unresolved.push_back(item);
        } else {
          std::unique_ptr<addrinfo, decltype(&freeaddrinfo)> guard(res, &freeaddrinfo);
          for (const addrinfo* a = res; a != nullptr; a = a->ai_next) {
            char text[INET_ADDRSTRLEN] = {};
            const auto* sin = reinterpret_cast<const sockaddr_in*>(a->ai_addr);
            if (inet_ntop(AF_INET, &sin->sin_addr, text, sizeof text) != nullptr) add(text);
          }
        }
      }
    }
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace pheromesh::bus
