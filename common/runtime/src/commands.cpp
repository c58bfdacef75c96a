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
// Every field equal: a copy of the same signed command.
bool same(const core::CommandMsg& a, const core::CommandMsg& b) {
  return a.issuer == b.issuer && a.seq == b.seq && a.issued_ms == b.issued_ms && a.kind == b.kind && a.x == b.x &&
         a.y == b.y && a.w == b.w && a.h == b.h && a.mac == b.mac;
}
}  // namespace

SwarmCommands::SwarmCommands(bus::Bus& bus, std::shared_ptr<spdlog::logger> log)
    : bus_(&bus), log_(std::move(log)), gate_(key_or_log(*log_)) {
  bus_->subscribe_commands();
}

std::vector<core::CommandMsg> SwarmCommands::take() {
  inbox_.clear();
  bus_->take_commands(inbox_);
  // A UAV hears each command from its home and its backup place agent
  // (docs/architecture.md, "Relays"): a copy of one it admitted, with the
  // same signature, is no replay.
  std::map<std::pair<uint32_t, uint32_t>, core::CommandMsg> batch;
  std::erase_if(inbox_, [&](const core::CommandMsg& c) {
    auto it = admitted_.find({c.issuer, c.seq});
    if (it != admitted_.end() && same(it->second, c)) return true;
    auto [in_batch, first] = batch.try_emplace({c.issuer, c.seq}, c);
    return !first && same(in_batch->second, c);
  });
  if (inbox_.empty()) return {};
  std::vector<std::string> refused;
  auto ok = gate_.admit(inbox_, &refused);
  for (const auto& r : refused) {
    if (gate_.rejected() <= 20) log_->warn("ignored ground-station command {}", r);
  }
  for (const auto& c : ok) {
    admitted_[{c.issuer, c.seq}] = c;
    const bool toggle = c.kind == static_cast<uint8_t>(core::CommandKind::Pause) ||
                        c.kind == static_cast<uint8_t>(core::CommandKind::Resume);
    uint32_t& last_toggle = toggle_seq_[c.issuer];
    // A pause or resume older than the last one applied changes nothing:
    // the newer one stands (each arrives once, in no set order: CommandGate).
    if (toggle && c.seq < last_toggle) {
      log_->info("ground-station command {} (seq {}) arrived after seq {}, which stands", auth::describe(c), c.seq,
                 last_toggle);
      continue;
    }
    log_->info("ground-station command {} (seq {})", auth::describe(c), c.seq);
    if (toggle) last_toggle = c.seq;
    if (c.kind == static_cast<uint8_t>(core::CommandKind::Pause)) paused_ = true;
    if (c.kind == static_cast<uint8_t>(core::CommandKind::Resume)) paused_ = false;
    if (c.kind == static_cast<uint8_t>(core::CommandKind::Start)) started_ = true;
    if (c.kind == static_cast<uint8_t>(core::CommandKind::End)) ended_ = true;
  }
  return ok;
}

}  // namespace pheromesh::runtime
