// A host speed-up, no hardware: the PEs' NN/kNN scans of an exact search run on a second host
// thread while the event loop goes on. Timing never depends on what a scan finds there (a
// batch's cycles come from its Node Set's size, not its results): only the query's result
// slot does, and the slot is next read by the query's next Recursion Unit walk, thousands of
// cycles later. So a Search Unit submits the scan and moves on; the RU waits for the slot's
// last scan before it walks (almost always long done). Scans run in submission order, each
// slot's in the order the simulation issued them, so the results are the same bit for bit as
// with the scans inline. Radius hits and approximate search (whose Leader Buffer decisions
// the timing reads at once) stay inline.
//
// The thread sleeps while there is little to do: it is woken once a batch of scans waits, or
// when the event loop needs a slot, so an idle worker does not take a core from other runs.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "hw/be/leaf_bounds.hpp"
#include "hw/be/pe_array.hpp"
#include "hw/job.hpp"

namespace tigris::hw {

class ScanWorker {
 public:
  ScanWorker() = default;
  ~ScanWorker();
  ScanWorker(const ScanWorker&) = delete;
  ScanWorker& operator=(const ScanWorker&) = delete;

  // A job starts with `slots` result slots. `threaded` false: every scan runs inline in
  // submit(); true: on the worker thread (started the first time it is asked for).
  void start(std::uint32_t slots, bool threaded);
  bool threaded() const { return threaded_; }
  // PE `pe` scans `count` entries of `set` (within `box`) for `token` into its result slot.
  void submit(PeArray& pe, const QueryToken& token, const tlm_if::PointEntry* set, std::uint32_t count,
              const LeafBounds::Box* box);
  // Returns once every scan submitted for `slot` has written it.
  void wait_slot(std::uint32_t slot) {
    if (slot_ticket_[slot] > seen_done_) wait(slot_ticket_[slot]);
  }
  void drain() { wait(submitted_); }  // every scan submitted so far is done
  // Warms what wait_slot(`slot`) reads (the query's walk is a few dispatches away).
  void prefetch(std::uint32_t slot) const {
    if (threaded_) __builtin_prefetch(slot_ticket_.data() + slot);
  }

 private:
  struct Job {
    PeArray* pe;
    QueryToken token;
    const tlm_if::PointEntry* set;
    const LeafBounds::Box* box;
    std::uint32_t count;
  };
  static constexpr std::size_t kRing = 4096;      // jobs in flight at most (a power of two)
  static constexpr std::uint64_t kWakeBatch = 256;  // pending jobs that wake a sleeping worker
  void wait(std::uint64_t ticket);
  void wake();
  void run();

  bool threaded_ = false;
  std::vector<Job> ring_ = std::vector<Job>(kRing);
  std::vector<std::uint64_t> slot_ticket_;  // per slot, the ticket of its last scan (event loop only)
  std::uint64_t submitted_ = 0;             // jobs published (event loop only)
  // done_ as the event loop last read it: done_'s cache line moves to the worker's core at every
  // scan, so the event loop reads it only when this falls short (a few times per thousand scans).
  std::uint64_t seen_done_ = 0;
  alignas(64) std::atomic<std::uint64_t> published_{0};  // ring entries below this are ready
  alignas(64) std::atomic<std::uint64_t> done_{0};       // jobs below this have run
  alignas(64) std::atomic<bool> sleeping_{false};
  std::atomic<bool> stop_{false};
  std::atomic<bool> wake_{false};  // the worker is asked to run
  std::mutex mutex_;
  std::condition_variable cv_;
  std::thread thread_;
};

}  // namespace tigris::hw
