#include "threaded_scans.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace tigris::hw {

namespace {

void relax() {
#if defined(__SSE2__)
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

}  // namespace

ThreadedScans::~ThreadedScans() {
  if (!thread_.joinable()) return;
  stop_.store(true);
  wake_.store(false);
  wake();
  thread_.join();
}

void ThreadedScans::begin(std::uint32_t slots) {
  drain();
  seen_done_ = submitted_;
  slot_ticket_.assign(slots, 0);
  if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
}

void ThreadedScans::scan(PeArray& pe, const QueryToken& token, std::uint32_t leaf, const tlm_if::PointEntry* set,
                         std::uint32_t count) {
  if (submitted_ - seen_done_ >= kRing) wait(submitted_ - kRing + 1);  // the ring is full
  ring_[submitted_ & (kRing - 1)] = Job{&pe, token, set, &box(leaf), count};
  __builtin_prefetch(&ring_[(submitted_ + 8) & (kRing - 1)], 1);  // the worker read it last
  slot_ticket_[token.slot] = ++submitted_;
  published_.store(submitted_, std::memory_order_seq_cst);
  if (submitted_ - seen_done_ >= kWakeBatch) {  // many may wait: is the worker at it?
    seen_done_ = done_.load(std::memory_order_acquire);
    if (submitted_ - seen_done_ >= kWakeBatch && sleeping_.load(std::memory_order_seq_cst)) wake();
  }
}

void ThreadedScans::wait(std::uint64_t ticket) {
  for (unsigned spins = 0; (seen_done_ = done_.load(std::memory_order_acquire)) < ticket; ++spins) {
    if (sleeping_.load(std::memory_order_seq_cst)) wake();
    if (spins < 4096)
      relax();
    else
      std::this_thread::yield();  // the worker may share our core
  }
}

void ThreadedScans::wake() {
  if (wake_.exchange(true)) return;              // asked already: one notification per sleep
  { std::lock_guard<std::mutex> lock(mutex_); }  // the worker is in cv_.wait or sees wake_ before it
  cv_.notify_one();
}

void ThreadedScans::run() {
  std::uint64_t next = 0;  // only this thread advances done_
  for (;;) {
    const std::uint64_t published = published_.load(std::memory_order_acquire);
    if (next < published) {
      const Job& j = ring_[next & (kRing - 1)];
      if (next + 1 < published) {  // warm the next job's slot
        const Job& n = ring_[(next + 1) & (kRing - 1)];
        write_soon(n.pe->slots().address(n.token.slot), n.pe->slots().bytes());
      }
      if (!fruitless(*j.pe, j.token, *j.box)) j.pe->scan_nearest(j.token, j.set, j.count);  // the bound as of now
      done_.store(++next, std::memory_order_release);
      continue;
    }
    // Nothing to do: sleep until a batch of scans waits or the event loop needs a slot.
    std::unique_lock<std::mutex> lock(mutex_);
    sleeping_.store(true, std::memory_order_seq_cst);
    if (next >= published_.load(std::memory_order_seq_cst)) cv_.wait(lock, [this] { return wake_.load(); });
    sleeping_.store(false, std::memory_order_seq_cst);
    wake_.store(false);
    if (stop_.load() && next >= published_.load(std::memory_order_acquire)) return;
  }
}

}  // namespace tigris::hw
