// Who may write as a key (a UAV id): the first writer whose sample was
// accepted for it, until it departs or falls silent (issue 28,
// docs/architecture.md "What a receiver refuses"). On an open domain any process can write any topic, and a
// plausible forgery (a state one cell from the real UAV, a tick ahead) passes
// every check of the sample itself; what the forger cannot copy is its writer,
// which the receiving bus names (UavStateMsg::writer). The lockstep clock is
// latched the same way (core::LockstepFollower). Pure, no I/O.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <unordered_map>

namespace pheromesh::core {

class WriterLatch {
 public:
  using Clock = std::chrono::steady_clock;

  // `takeover_after`: a writer that has written nothing for this long gives
  // the key up to the next writer heard - a restarted UAV is a new writer,
  // which keeps the UAV's instance alive, so the old writer's going is no
  // departure. nullopt: only release() frees a key.
  explicit WriterLatch(std::optional<Clock::duration> takeover_after = std::nullopt)
      : takeover_after_(takeover_after) {}

  // True if `writer` may write as `key`: it holds the latch, the key is
  // free, or its holder has been silent for the takeover time. Writer 0 (a
  // transport that cannot tell) may always.
  [[nodiscard]] bool allows(uint32_t key, uint64_t writer, Clock::time_point now) const;
  // `writer`'s sample as `key` was accepted (allowed, and it passed the
  // receiver's other checks): it holds the key from now on, heard at `now`.
  // A refused sample latches nothing, so a forger cannot take a free key
  // with a sample the receiver refuses anyway.
  void hold(uint32_t key, uint64_t writer, Clock::time_point now);
  // A sample of `writer` as `key` arrived (not yet judged): if `writer`
  // holds the key, it is not silent. A receiver calls it for every sample
  // of a take before it judges any: one that stalled past the takeover time
  // would otherwise take its holder for silent and give the key to a
  // forged sample queued ahead of the holder's own.
  void heard(uint32_t key, uint64_t writer, Clock::time_point now);
  // The key's writer departed (every writer of the key vanished): the next
  // writer heard holds it.
  void release(uint32_t key);
  // The key's writer departed, perhaps only for a while (its liveliness
  // lapsed under packet loss): any writer may take the key now, but its
  // holder keeps it - and counts in holds_any - until another writer holds
  // it. Heard again (heard), the holder closes the key again.
  void open(uint32_t key);
  [[nodiscard]] std::optional<uint64_t> holder(uint32_t key) const;
  // The key is held by a writer not silent for the takeover time.
  [[nodiscard]] bool held(uint32_t key, Clock::time_point now) const;
  // When the key's holder was last heard (hold or heard); nullopt if free.
  [[nodiscard]] std::optional<Clock::time_point> last_heard(uint32_t key) const;
  // `writer` holds some key: the ground station takes what place agents
  // relay (states, detections, tiles) only from a process that holds a
  // place agent's id. Writer 0 (unknown) always does.
  [[nodiscard]] bool holds_any(uint64_t writer) const { return writer == 0 || keys_of_.contains(writer); }

 private:
  struct Held {
    uint64_t writer = 0;
    Clock::time_point last{};
    bool open = false;  // open(): any writer may take it
  };
  void drop_holder(uint64_t writer);
  std::optional<Clock::duration> takeover_after_;
  std::unordered_map<uint32_t, Held> held_;
  std::unordered_map<uint64_t, uint32_t> keys_of_;  // writer -> how many keys it holds
};

}  // namespace pheromesh::core
