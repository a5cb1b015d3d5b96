// The accelerator's one event loop (DESIGN.md sections 7 and 18). Units ask to be woken at a
// cycle, with sc_event's rule: an earlier request replaces a later pending one, a later one is
// ignored. Work due in the same cycle runs in a fixed order, the unit's rank then its id:
// the front-end's dispatch, then the Recursion Units by id, then the Search Units by id; a unit
// woken for the current cycle by another's action runs in that cycle after it. So same-cycle
// requests for a shared resource (SRAM banks and ports, QDN ports, the write-back) are served
// by unit priority, never in SystemC's process order: an accelerator gives the same cycles
// alone or beside others, whatever order its units were built in. One SystemC method per
// accelerator runs the loop, waking only at cycles with work.
#pragma once

#include <cstdint>
#include <limits>
#include <algorithm>
#include <vector>

#include <systemc>

#include "hw/clock.hpp"

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
    cycle = std::max(cycle, clock_.now());
    if (c.pending_ != kNever) unmark(c.order_, c.pending_);
    c.pending_ = kNever;  // so a resize in mark() does not book it twice
    mark(c.order_, cycle);
    c.pending_ = cycle;
    if (!running_) tick_.notify(clock_.until(cycle));  // inside the loop, run() re-arms itself
  }
  void now(Client& c) { at(c, clock_.now()); }
  // A job starts: forget every pending wake-up.
  void reset() {
    for (Client* c : clients_) c->pending_ = kNever;
    resize(kInitialCycles);
  }
  // Registers a unit (at construction); keeps the clients in (rank, id) order.
  void add(Client& c) {
    clients_.insert(std::upper_bound(clients_.begin(), clients_.end(), &c,
                                     [](const Client* a, const Client* b) { return a->key_ < b->key_; }),
                    &c);
    for (std::uint32_t i = 0; i < clients_.size(); ++i) clients_[i]->order_ = i;
    words_ = (clients_.size() + 63) / 64;
    resize(kInitialCycles);
  }

 private:
  // Pending wake-ups: a ring of cycles, each a bit set over the clients in (rank, id) order, so
  // the loop takes a cycle's clients lowest first; `cycles_` marks the ring's non-empty cycles.
  // Every pending cycle c has now <= c < now + ring (the ring doubles when a wake-up is further).
  static constexpr std::size_t kInitialCycles = 1024;
  std::uint64_t* set_of(std::uint64_t cycle) { return bits_.data() + (cycle & (ring_ - 1)) * words_; }
  void mark(std::uint32_t order, std::uint64_t cycle) {
    while (cycle - clock_.now() >= ring_) resize(ring_ * 2);
    ++waiting_;
    set_of(cycle)[order / 64] |= std::uint64_t{1} << (order % 64);
    const std::size_t r = static_cast<std::size_t>(cycle & (ring_ - 1));
    cycles_[r / 64] |= std::uint64_t{1} << (r % 64);
  }
  void unmark(std::uint32_t order, std::uint64_t cycle) {
    std::uint64_t* set = set_of(cycle);
    set[order / 64] &= ~(std::uint64_t{1} << (order % 64));
    --waiting_;
    for (std::size_t w = 0; w < words_; ++w)
      if (set[w]) return;
    const std::size_t r = static_cast<std::size_t>(cycle & (ring_ - 1));
    cycles_[r / 64] &= ~(std::uint64_t{1} << (r % 64));
  }
  // The earliest cycle with a pending wake-up at or after `from` (some client is pending).
  std::uint64_t next_cycle(std::uint64_t from) const {
    const std::size_t mask = ring_ - 1;
    std::size_t r = static_cast<std::size_t>(from & mask);
    for (std::size_t scanned = 0;;) {
      const std::uint64_t w = cycles_[r / 64] >> (r % 64);
      if (w != 0) return from + scanned + static_cast<std::uint64_t>(__builtin_ctzll(w));
      const std::size_t step = 64 - r % 64;
      scanned += step;
      r = (r + step) & mask;
    }
  }
  void resize(std::size_t cycles) {
    ring_ = cycles;
    bits_.assign(ring_ * words_, 0);
    cycles_.assign((ring_ + 63) / 64, 0);
    waiting_ = 0;
    for (Client* c : clients_)
      if (c->pending_ != kNever) mark(c->order_, c->pending_);
  }
  void run() {
    const std::uint64_t now = clock_.now();
    running_ = true;
    if (waiting_ > 0) {
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
        c->wake();
        set = set_of(now);  // a wake-up far ahead may have grown the ring
        w = 0;
      }
    }
    running_ = false;
    if (waiting_ > 0) tick_.notify(clock_.until(next_cycle(now)));
  }

  Clock clock_;
  std::vector<Client*> clients_;  // in (rank, id) order
  std::size_t words_ = 0;         // 64-bit words per cycle's set
  std::size_t ring_ = 0;          // cycles in the ring (a power of two)
  std::vector<std::uint64_t> bits_, cycles_;
  std::size_t waiting_ = 0;       // clients with a wake-up
  sc_core::sc_event tick_;
  bool running_ = false;
};

}  // namespace tigris::hw
