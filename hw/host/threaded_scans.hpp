// The scan service (hw/host/scan_service.hpp) with the NN/kNN scans of an exact search on a
// second host thread while the event loop goes on (`--sim-threads 2`). A Search Unit submits a
// scan and moves on; the RU's ready() waits for the slot's last scan before it walks (almost
// always long done). Scans run in submission order, so each slot's run in the order the
// simulation issued them, and the results are bit for bit those of InlineScans.
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

#include "hw/be/pe_array.hpp"
#include "scan_service.hpp"

namespace tigris::hw {

class ThreadedScans final : public ScanService {
 public:
  ThreadedScans() = default;
  ~ThreadedScans() override;
  ThreadedScans(const ThreadedScans&) = delete;
  ThreadedScans& operator=(const ThreadedScans&) = delete;

  void scan(PeArray& pe, const QueryToken& token, std::uint32_t leaf, const tlm_if::PointEntry* set,
            std::uint32_t count) override;
  void ready(std::uint32_t slot) override {
    if (slot_ticket_[slot] > seen_done_) wait(slot_ticket_[slot]);
  }
  void drain() override { wait(submitted_); }
  // Warms what ready() reads. The slot itself is written on the worker's core: not warmed here.
  void walk_soon(const QueryToken& token) override {
    __builtin_prefetch(slot_ticket_.data() + token.slot);
    hint(token.query);
  }
  void queued(const PeArray&, const QueryToken& token) override { hint(token.query); }

 private:
  void begin(std::uint32_t slots) override;  // the worker thread starts with the first job
  struct Job {
    PeArray* pe;
    QueryToken token;
    const tlm_if::PointEntry* set;
    const LeafBounds::Box* box;
    std::uint32_t count;
  };
  static constexpr std::size_t kRing = 4096;        // jobs in flight at most (a power of two)
  static constexpr std::uint64_t kWakeBatch = 256;  // pending jobs that wake a sleeping worker
  void wait(std::uint64_t ticket);
  void wake();
  void run();

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
