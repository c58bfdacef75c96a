// The ground station's line to `pheromesh run` (the launcher): kill and
// restart requests from the console, and pause/resume so that the launcher
// extends its deadline. One request per line ("kill uav 3"); the launcher
// answers one line, "ok <what it did>" or "error <why not>".
#pragma once

#include <chrono>
#include <string>

#include "pheromesh/console/server.hpp"

namespace pheromesh::console {

class LauncherLink {
 public:
  // `fd`: the socket the launcher passed (--launcher-fd); -1: no launcher.
  explicit LauncherLink(int fd, std::chrono::milliseconds timeout = std::chrono::seconds(5)) : fd_(fd), timeout_(timeout) {}
  [[nodiscard]] bool connected() const { return fd_ >= 0; }
  // 200 and the launcher's words for "ok ..."; 409 for "error ..." and when
  // there is no launcher or it is gone; 504 when it does not answer in time.
  ConsoleSource::Answer ask(const std::string& request) const;

 private:
  int fd_;
  std::chrono::milliseconds timeout_;
};

}  // namespace pheromesh::console
