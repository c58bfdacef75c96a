#include "console_live.hpp"

#include <chrono>
#include <utility>

#include "pheromesh/console/view.hpp"

namespace pheromesh::groundstation {

LiveConsole::LiveConsole(console::ConsoleInfo info, ControlStatus control)
    : info_(std::move(info)), control_(std::move(control)), state_(console::initial_state(info_)) {}

void LiveConsole::publish(const console::Frame& f) {
  {
    std::lock_guard lock(mu_);
    console::apply(state_, f);
  }
  cv_.notify_all();
}

void LiveConsole::set_metrics(std::string text) {
  std::lock_guard lock(mu_);
  metrics_ = std::move(text);
}

std::vector<std::unique_ptr<LiveConsole::Pending>> LiveConsole::take_pending() {
  std::lock_guard lock(mu_);
  std::vector<std::unique_ptr<Pending>> out;
  while (!pending_.empty()) {
    out.push_back(std::move(pending_.front()));
    pending_.pop_front();
  }
  return out;
}

void LiveConsole::close() {
  std::lock_guard lock(mu_);
  closed_ = true;
  for (auto& p : pending_) p->done.set_value({503, "the ground station is shutting down"});
  pending_.clear();
  cv_.notify_all();
}

nlohmann::json LiveConsole::info() {
  nlohmann::json j;
  j["mode"] = "live";
  j["scenario"] = console::info_json(info_);
  j["control"] = {{"enabled", control_.enabled}, {"process_control", control_.process_control}, {"reason", control_.reason}};
  return j;
}

nlohmann::json LiveConsole::frame(uint16_t layer, uint64_t since, std::optional<double> /*t*/, bool wait) {
  std::unique_lock lock(mu_);
  if (wait && since != 0 && since >= state_.version) {
    cv_.wait_for(lock, std::chrono::seconds(1), [&] { return closed_ || state_.version > since; });
  }
  return console::frame_json(state_, info_, layer, since);
}

console::ConsoleSource::Answer LiveConsole::command(const nlohmann::json& body, const std::string& who) {
  auto p = std::make_unique<Pending>();
  p->body = body;
  p->who = who;
  auto fut = p->done.get_future();
  {
    std::lock_guard lock(mu_);
    if (closed_) return {503, "the ground station is shutting down"};
    pending_.push_back(std::move(p));
  }
  if (fut.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
    return {503, "the ground station did not handle the command within 10 s"};
  }
  return fut.get();
}

void LiveConsole::refused(console::Refusal reason, int status, const std::string& who, const std::string& what) {
  std::lock_guard lock(refused_mu_);
  if (refused_.size() >= kMaxQueuedRefusals) {
    ++refused_overflow_;
    return;
  }
  refused_.push_back({reason, status, who, what.substr(0, 200)});
}

std::vector<LiveConsole::Refused> LiveConsole::take_refused(uint64_t& overflowed) {
  std::lock_guard lock(refused_mu_);
  overflowed = std::exchange(refused_overflow_, 0);
  return std::exchange(refused_, {});
}

std::string LiveConsole::metrics() {
  std::lock_guard lock(mu_);
  return metrics_;
}

}  // namespace pheromesh::groundstation
