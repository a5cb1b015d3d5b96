// The accelerator's one event loop (docs/model.md, timing). Units ask to be woken at a
// cycle, with sc_event's rule: an earlier request replaces a later pending one, a later one is
// ignored. Work due in the same cycle runs in a fixed order, the unit's rank then its id:
// the front-end's dispatch, then the Recursion Units by id, then the Search Units by id; a unit
// woken for the current cycle by another's action runs in that cycle after it. So same-cycle
// requests for a shared resource (SRAM banks and ports, QDN ports, the write-back) are served
// by unit priority, never in SystemC's process order: an accelerator gives the same cycles
// alone or beside others, whatever order its units were built in. One SystemC method per
// accelerator runs the loop, waking only at cycles with work.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <queue>
#include <vector>

#include <systemc>

#include "clock.hpp"

namespace tigris::hw {

class Scheduler : public sc_core::sc_module {
 public:
  static constexpr std::uint64_t kNever = std::numeric_limits<std::uint64_t>::max();
  enum Rank : std::uint32_t { kFrontEnd = 0, kRecursionUnit = 1, kSearchUnit = 2 };

  // A unit the loop wakes: its wake() runs at the cycles it asked for.
  class Client {
   public:
    Client(Rank rank, std::uint32_t id) : key_((std::uint64_t{rank} << 32) | id) {}
    virtual ~Client() = default;
    virtual void wake() = 0;

   private:
    friend class Scheduler;
    std::uint64_t key_;
    std::uint32_t order_ = 0;  // position in (rank, id) order among the clients
    std::uint64_t pending_ = kNever;
    bool in_ring_ = false;  // its wake-up is in the ring (else in the far heap)
  };

  SC_HAS_PROCESS(Scheduler);
  Scheduler(sc_core::sc_module_name name, Clock clock) : sc_module(name), clock_(clock) {
    SC_METHOD(run);
    sensitive << tick_;
    dont_initialize();
  }

  // Wakes `c` at `cycle` (not before now).
  void at(Client& c, std::uint64_t cycle) {
    if (c.pending_ <= cycle) return;
    prepare();
    const std::uint64_t now = clock_.now();
    cycle = std::max(cycle, now);
    if (c.pending_ != kNever && c.in_ring_) unmark(c.order_, c.pending_);  // a far one goes stale
    c.pending_ = cycle;
    place(c, now);
    if (!running_) tick_.notify(clock_.until(cycle));  // inside the loop, run() re-arms itself
  }
  void now(Client& c) { at(c, clock_.now()); }
  // A job starts: forget every pending wake-up.
  void reset() {
    prepare();
    for (Client* c : clients_) c->pending_ = kNever, c->in_ring_ = false;
    std::fill(bits_.begin(), bits_.end(), 0);
    std::fill(cycles_.begin(), cycles_.end(), 0);
    far_ = {};
  }
  // Registers a unit (at construction).
  void add(Client& c) {
    clients_.push_back(&c);
    sorted_ = false;
  }

 private:
  // Pending wake-ups: a ring of the next kRing cycles, each a bit set over the clients in (rank,
  // id) order, so the loop takes a cycle's clients lowest first (`cycles_` marks the ring's
  // non-empty cycles); a wake-up further ahead waits in a heap and moves into the ring once its
  // cycle comes within reach. A replaced far wake-up is left in the heap and skipped as stale.
  static constexpr std::uint64_t kRing = 1024;
  struct Far {
    std::uint64_t cycle;
    Client* client;
    bool operator>(const Far& o) const { return cycle > o.cycle; }
  };
  // Sorts the clients into (rank, id) order once they are all added.
  void prepare() {
    if (sorted_) return;
    std::sort(clients_.begin(), clients_.end(), [](const Client* a, const Client* b) { return a->key_ < b->key_; });
    for (std::uint32_t i = 0; i < clients_.size(); ++i) clients_[i]->order_ = i;
    words_ = (clients_.size() + 63) / 64;
    bits_.assign(kRing * words_, 0);
    cycles_.assign(kRing / 64, 0);
    sorted_ = true;
    far_ = {};
    for (Client* c : clients_)  // a unit added after wake-ups were asked for: place them again
      if (c->pending_ != kNever) place(*c, clock_.now());
  }
  std::uint64_t* set_of(std::uint64_t cycle) { return bits_.data() + (cycle % kRing) * words_; }
  void place(Client& c, std::uint64_t now) {
    c.in_ring_ = c.pending_ - now < kRing;
    if (!c.in_ring_) {
      far_.push({c.pending_, &c});
      return;
    }
    set_of(c.pending_)[c.order_ / 64] |= std::uint64_t{1} << (c.order_ % 64);
    const std::size_t r = static_cast<std::size_t>(c.pending_ % kRing);
    cycles_[r / 64] |= std::uint64_t{1} << (r % 64);
  }
  void unmark(std::uint32_t order, std::uint64_t cycle) {
    std::uint64_t* set = set_of(cycle);
    set[order / 64] &= ~(std::uint64_t{1} << (order % 64));
    for (std::size_t w = 0; w < words_; ++w)
      if (set[w]) return;
    const std::size_t r = static_cast<std::size_t>(cycle % kRing);
    cycles_[r / 64] &= ~(std::uint64_t{1} << (r % 64));
  }
  // Moves the far wake-ups now within the ring's reach into it; drops replaced ones.
  void pull_far(std::uint64_t now) {
    while (!far_.empty() && far_.top().cycle < now + kRing) {
      const Far f = far_.top();
      far_.pop();
      if (f.client->pending_ == f.cycle && !f.client->in_ring_) place(*f.client, now);
    }
    while (!far_.empty() && far_.top().client->pending_ != far_.top().cycle) far_.pop();
  }
  // The earliest pending cycle at or after `now`, or kNever.
  std::uint64_t next_cycle(std::uint64_t now) const {
    std::size_t r = static_cast<std::size_t>(now % kRing);
    for (std::uint64_t scanned = 0; scanned < kRing;) {
      const std::uint64_t w = cycles_[r / 64] >> (r % 64);
      if (w != 0) return now + scanned + static_cast<std::uint64_t>(__builtin_ctzll(w));
      const std::size_t step = 64 - r % 64;
      scanned += step;
      r = (r + step) % kRing;
    }
    return far_.empty() ? kNever : far_.top().cycle;
  }
  void run() {
    const std::uint64_t now = clock_.now();
    running_ = true;
    pull_far(now);
    std::uint64_t* set = set_of(now);
    for (std::size_t w = 0; w < words_;) {  // lowest order first; a wake may add lower ones
      if (set[w] == 0) {
        ++w;
        continue;
      }
      const std::uint32_t order = static_cast<std::uint32_t>(w * 64 + __builtin_ctzll(set[w]));
      Client* c = clients_[order];
      unmark(order, now);
      c->pending_ = kNever;
      c->in_ring_ = false;
      c->wake();
      w = 0;
    }
    running_ = false;
    pull_far(now);
    const std::uint64_t next = next_cycle(now);
    if (next != kNever) tick_.notify(clock_.until(next));
  }

  Clock clock_;
  std::vector<Client*> clients_;  // in (rank, id) order once prepared
  bool sorted_ = false;
  std::size_t words_ = 0;  // 64-bit words per cycle's set
  std::vector<std::uint64_t> bits_, cycles_;
  std::priority_queue<Far, std::vector<Far>, std::greater<Far>> far_;
  sc_core::sc_event tick_;
  bool running_ = false;
};

}  // namespace tigris::hw
