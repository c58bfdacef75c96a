// A UAV's account of its own deposits (docs/faults.md, "No silent loss"):
// each deposit it writes stays unconfirmed until a view from its home place
// agent says that agent received that sequence number (View.deposit_ack).
// What is still unconfirmed when the UAV ends is what it counts as lost.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "pheromesh/core/messages.hpp"

namespace pheromesh::core {

class DepositReceipts {
 public:
  // Sequence numbers are strictly increasing per UAV (restarts continue above).
  void sent(uint32_t seq) { pending_.push_back(seq); }
  // The home place agent received every deposit from `from` up to `ack`
  // (View.deposit_ack_from, .deposit_ack). One below `from` never reached
  // it: it was sent while the place agent was dead and started again (its
  // new life reads no history), so it stays unconfirmed for good.
  void confirmed(uint32_t from, uint32_t ack) {
    while (!pending_.empty() && pending_.front() < from) {
      pending_.pop_front();
      ++abandoned_;
    }
    while (!pending_.empty() && pending_.front() <= ack) pending_.pop_front();
  }
  [[nodiscard]] std::size_t unconfirmed() const { return pending_.size() + abandoned_; }
  // Those the current place agent may still confirm.
  [[nodiscard]] std::size_t pending() const { return pending_.size(); }
  // The place agent these went to is gone (the UAV moves to its backup
  // gateway): what it did not confirm stays unconfirmed for good - the
  // backup's acknowledgements cover only what reached the backup.
  void abandon() {
    abandoned_ += pending_.size();
    pending_.clear();
  }

 private:
  std::deque<uint32_t> pending_;
  std::size_t abandoned_ = 0;
};

// The place agent's side: the highest deposit seq received from each home
// UAV, which its views confirm (View.deposit_ack). Only a seq the UAV can
// have reached counts (core/plausibility.hpp check_seq_reachable): one forged
// far ahead would confirm every deposit the UAV sends from then on.
class HomeAcks {
 public:
  // A deposit of `uav` with `seq` arrived at place tick `tick`.
  void received(uint32_t uav, uint32_t seq, uint32_t tick);
  // What the next view of `uav` confirms (0: nothing yet).
  [[nodiscard]] uint32_t ack(uint32_t uav) const;
  // The first seq of `uav` this process received (0: none): it confirms
  // nothing below it (DepositReceipts::confirmed).
  [[nodiscard]] uint32_t ack_from(uint32_t uav) const;

 private:
  std::map<uint32_t, std::pair<uint32_t, uint32_t>> last_;  // uav -> (seq, tick it came at)
  std::map<uint32_t, uint32_t> first_;                      // uav -> the first seq accepted
};

// A swarm with standbys sees the same deposit twice (both replicas of a home
// forward it; lockstep UAVs re-send theirs after a quiet spell); the copies
// arrive within a tick or so. Remembers, per UAV, which of the `window`
// seqs up to the highest seen so far were seen: one bit each, so at most
// window / 8 bytes per UAV however long the run (a std::set of the newest
// 4096 seqs took ~48 bytes per seq, up to ~200 KiB per UAV: ~4.5 MiB in a
// place agent of a 23-UAV soak, growing for as long as the run, issue 28).
// A seq `window` or more below the highest is too old to tell: not a copy.
// A seq further ahead than the UAV can have deposited by now
// (check_seq_reachable) is neither a copy nor remembered: a forged one would
// push every real seq out of the window.
class SeenDeposits {
 public:
  explicit SeenDeposits(uint32_t window = 4096);
  // True if (uav, seq) was seen before; remembers it otherwise. `tick`: the
  // receiver's tick now.
  bool seen_before(uint32_t uav, uint32_t seq, uint32_t tick);
  // True if (uav, seq) was seen before; remembers nothing.
  [[nodiscard]] bool seen(uint32_t uav, uint32_t seq) const;
  // Bytes held for the seqs of every UAV seen (the bound: UAVs x window / 8).
  [[nodiscard]] std::size_t bytes() const;

 private:
  struct Window {
    uint32_t top = 0;             // the highest seq seen
    uint32_t top_tick = 0;        // the receiver's tick when it was seen
    std::vector<uint64_t> bits;   // bit (seq % window): seq in (top - window, top] was seen
  };
  [[nodiscard]] bool bit(const Window& w, uint32_t seq) const;
  void set_bit(Window& w, uint32_t seq, bool on) const;
  uint32_t window_;
  std::map<uint32_t, Window> seen_;
};

// Where a place agent sends each deposit it takes: apply it here (its own
// region's, or one for no region at all, which PlaceCore rejects with the
// reason), forward it to the owner's place agent, or drop it as a copy taken
// before (`drop_copies`: swarms with standbys, whose replicas both forward,
// and lockstep runs, whose UAVs and place agents re-send deposits after a
// quiet spell, bus/resend.hpp; elsewhere a repeated sequence number is a
// replay, which PlaceCore rejects with its reason). It also notes what the
// home UAVs' views confirm.
enum class DepositRoute : uint8_t { Apply, Forward, Copy };
class DepositDesk {
 public:
  DepositDesk(uint32_t region, uint32_t regions, uint32_t swarm, bool drop_copies)
      : region_(region), regions_(regions), swarm_(swarm), drop_copies_(drop_copies) {}
  // A deposit taken at place tick `tick`.
  DepositRoute take(const DepositMsg& d, uint32_t tick);
  [[nodiscard]] uint32_t ack(uint32_t uav) const { return acks_.ack(uav); }
  [[nodiscard]] uint32_t ack_from(uint32_t uav) const { return acks_.ack_from(uav); }
  // From now on this place agent is also the gateway of `uav` (its backup):
  // its deposits are confirmed and counted like a home UAV's.
  void serve(uint32_t uav) { served_.insert(uav); }
  [[nodiscard]] uint64_t copies() const { return copies_; }
  // take() would drop `d` as a copy of one taken before.
  [[nodiscard]] bool is_copy(const DepositMsg& d) const { return drop_copies_ && seen_.seen(d.uav, d.seq); }
  // Distinct deposits taken from home UAV `uav` so far. Lockstep: a home
  // place agent holds every deposit its UAV wrote up to tick k (to apply or
  // to forward) once this reaches the deposits_sent of the UAV's state of k.
  [[nodiscard]] uint64_t taken_from(uint32_t uav) const;

 private:
  uint32_t region_, regions_, swarm_;
  bool drop_copies_;
  HomeAcks acks_;
  SeenDeposits seen_;
  uint64_t copies_ = 0;
  std::map<uint32_t, uint64_t> taken_from_;  // home UAV -> distinct deposits
  std::set<uint32_t> served_;                // UAVs it is the backup gateway of (serve)
};

}  // namespace pheromesh::core
