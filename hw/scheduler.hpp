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
#include <queue>
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
    c.pending_ = cycle;
    queue_.push({cycle, c.key_, &c});
    if (!running_) tick_.notify(clock_.until(cycle));  // inside the loop, run() re-arms itself
  }
  void now(Client& c) { at(c, clock_.now()); }
  // A job starts: forget every pending wake-up.
  void reset() {
    queue_ = {};
    for (Client* c : woken_) c->pending_ = kNever;
    woken_.clear();
  }
  void add(Client& c) { woken_.push_back(&c); }

 private:
  struct Entry {
    std::uint64_t cycle, key;
    Client* client;
    bool operator>(const Entry& o) const { return cycle != o.cycle ? cycle > o.cycle : key > o.key; }
  };
  void run() {
    const std::uint64_t now = clock_.now();
    running_ = true;
    while (!queue_.empty() && queue_.top().cycle <= now) {
      const Entry e = queue_.top();
      queue_.pop();
      if (e.client->pending_ != e.cycle) continue;  // replaced by an earlier request
      e.client->pending_ = kNever;
      e.client->wake();
    }
    running_ = false;
    if (!queue_.empty()) tick_.notify(clock_.until(queue_.top().cycle));
  }

  Clock clock_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue_;
  std::vector<Client*> woken_;  // every client, for reset()
  sc_core::sc_event tick_;
  bool running_ = false;
};

}  // namespace tigris::hw
