// The live side of the web console: the ground station's main thread
// publishes frames into it; the HTTP threads read them and queue commands,
// which the main thread executes (it alone touches the bus).
#pragma once

#include <condition_variable>
#include <deque>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "pheromesh/console/server.hpp"
#include "pheromesh/console/state.hpp"

namespace pheromesh::groundstation {

struct ControlStatus {
  bool enabled = false;          // commands accepted at all
  bool process_control = false;  // kill / restart (needs the launcher)
  std::string reason;            // why not, if either is false
};

class LiveConsole final : public console::ConsoleSource {
 public:
  LiveConsole(console::ConsoleInfo info, ControlStatus control);

  // --- main thread
  [[nodiscard]] const console::ConsoleState& state() const { return state_; }  // the only writer reads without the lock
  [[nodiscard]] const console::ConsoleInfo& console_info() const { return info_; }
  void publish(const console::Frame& f);
  void set_metrics(std::string text);
  struct Pending {
    nlohmann::json body;
    std::string who;
    std::promise<Answer> done;
  };
  std::vector<std::unique_ptr<Pending>> take_pending();
  struct Refused {
    console::Refusal reason;
    int status;
    std::string who, what;
  };
  // The refusals queued since the last call, and how many did not fit in
  // the queue (counted, not described).
  std::vector<Refused> take_refused(uint64_t& overflowed);
  void close();  // answers every waiting request; no more commands

  // --- HTTP threads
  nlohmann::json info() override;
  nlohmann::json frame(uint16_t layer, uint64_t since, std::optional<double> t, bool wait) override;
  Answer command(const nlohmann::json& body, const std::string& who) override;
  std::string metrics() override;
  void refused(console::Refusal reason, int status, const std::string& who, const std::string& what) override;

 private:
  console::ConsoleInfo info_;
  ControlStatus control_;
  std::mutex mu_;
  std::condition_variable cv_;
  console::ConsoleState state_;
  std::string metrics_;
  std::deque<std::unique_ptr<Pending>> pending_;
  bool closed_ = false;
  // Refused requests for the main thread to log, under their own lock so
  // that a flood of them never waits for a frame being served. Bounded: a
  // flood is summarised, not queued.
  static constexpr std::size_t kMaxQueuedRefusals = 256;
  std::mutex refused_mu_;
  std::vector<Refused> refused_;
  uint64_t refused_overflow_ = 0;
};

}  // namespace pheromesh::groundstation
