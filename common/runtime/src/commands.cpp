#include "pheromesh/runtime/commands.hpp"

#include <spdlog/spdlog.h>

namespace pheromesh::runtime {

namespace {
std::optional<auth::ControlKey> key_or_log(spdlog::logger& log) {
  auto k = auth::control_key_from_env();
  if (!k) {
    log.error("{}; ground-station commands will be ignored", k.error().message);
    return std::nullopt;
  }
  return k.value();
}
}  // namespace

SwarmCommands::SwarmCommands(bus::Bus& bus, std::shared_ptr<spdlog::logger> log)
    : bus_(&bus), log_(std::move(log)), gate_(key_or_log(*log_)) {
  bus_->subscribe_commands();
}

std::vector<core::CommandMsg> SwarmCommands::take() {
  inbox_.clear();
  bus_->take_commands(inbox_);
  if (inbox_.empty()) return {};
  std::vector<std::string> refused;
  auto ok = gate_.admit(inbox_, &refused);
  for (const auto& r : refused) {
    if (gate_.rejected() <= 20) log_->warn("ignored ground-station command {}", r);
  }
  for (const auto& c : ok) {
    log_->info("ground-station command {} (seq {})", auth::describe(c), c.seq);
    if (c.kind == static_cast<uint8_t>(core::CommandKind::Pause)) paused_ = true;
    if (c.kind == static_cast<uint8_t>(core::CommandKind::Resume)) paused_ = false;
    if (c.kind == static_cast<uint8_t>(core::CommandKind::Start)) started_ = true;
    if (c.kind == static_cast<uint8_t>(core::CommandKind::End)) ended_ = true;
  }
  return ok;
}

}  // namespace pheromesh::runtime
