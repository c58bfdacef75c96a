#include "pheromesh/mavlink/command_gate.hpp"

#include <algorithm>

namespace pheromesh::mavlink {

uint64_t CommandGate::malformed() const {
  const Decoder::Stats& d = decoder_.stats();
  return d.bad_crc + d.truncated + d.unknown_msgid + d.bad_flags + d.v1_frames;
}

CommandGate::Action CommandGate::action_of(const CommandLong& c) {
  const float p1 = c.param[0];
  if (c.command == kCmdDoPauseContinue) {
    if (p1 == 0.0F) return Action::Pause;
    if (p1 == 1.0F) return Action::Resume;
  } else if (c.command == kCmdComponentArmDisarm && p1 == 0.0F) {
    return Action::Stop;
  }
  return Action::Unsupported;
}

bool CommandGate::fresh(const Frame& f, uint64_t now_ts) {
  if (f.timestamp + kMaxAge < now_ts) return false;
  const Stream s{f.header.sysid, f.header.compid, f.link_id};
  auto it = streams_.find(s);
  if (it != streams_.end()) {
    if (f.timestamp <= it->second.newest) return false;
    it->second = {f.timestamp, ++use_};
    return true;
  }
  if (streams_.size() >= kMaxStreams) {
    const auto oldest = std::min_element(streams_.begin(), streams_.end(),
                                         [](const auto& a, const auto& b) { return a.second.used < b.second.used; });
    streams_.erase(oldest);
  }
  streams_.emplace(s, Seen{f.timestamp, ++use_});
  return true;
}

std::vector<CommandGate::Command> CommandGate::take(std::span<const uint8_t> datagram,
                                                    std::chrono::system_clock::time_point now) {
  std::vector<Command> out;
  const uint64_t now_ts = signing_timestamp(now);
  for (const Frame& f : decoder_.decode(datagram)) {
    if (f.header.msgid != CommandLong::kId) {
      ++stats_.other_messages;
      continue;
    }
    if (signatures_ == Signatures::Required) {
      if (!f.is_signed) {
        ++stats_.unsigned_refused;
        continue;
      }
      if (!key_ || !signature_valid(f, *key_)) {
        ++stats_.bad_signature;
        continue;
      }
      if (!fresh(f, now_ts)) {
        ++stats_.replayed;
        continue;
      }
    }
    Command c;
    c.message = CommandLong::from(f.payload);
    c.action = action_of(c.message);
    c.from_sysid = f.header.sysid;
    c.from_compid = f.header.compid;
    ++stats_.accepted;
    out.push_back(c);
  }
  return out;
}

}  // namespace pheromesh::mavlink
