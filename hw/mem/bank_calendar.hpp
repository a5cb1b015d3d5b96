// Which cycles one SRAM bank is busy in. Work items reserve their accesses when they start,
// some of them cycles ahead (a walk's later nodes, a stream's later words), so a single
// next-free time would make an access that comes later in simulation but earlier in cycles
// wait behind them. The calendar finds the first free cycle at or after the one asked for.
// It is a ring of 64-cycle blocks that doubles whenever a booking would overwrite a block
// that is still ahead of the current cycle.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace tigris::hw {

class BankCalendar {
 public:
  BankCalendar() : blocks_(64) {}  // a power of two, doubled as needed

  // Marks the first free cycle at or after `cycle` busy and returns it; `now` is the current
  // cycle (blocks wholly before it are free to reuse).
  std::uint64_t reserve(std::uint64_t cycle, std::uint64_t now) {
    cycle = next_free(cycle, now);
    book(cycle, now);
    return cycle;
  }
  // The first free cycle at or after `cycle`, not booked.
  std::uint64_t next_free(std::uint64_t cycle, std::uint64_t now) {
    for (;;) {
      const Block& b = block(cycle / 64, now);
      const std::uint64_t free = ~b.busy >> (cycle % 64);
      if (free != 0) return cycle + static_cast<std::uint64_t>(__builtin_ctzll(free));
      cycle = (cycle / 64 + 1) * 64;  // this block is full from here on
    }
  }
  void book(std::uint64_t cycle, std::uint64_t now) { block(cycle / 64, now).busy |= std::uint64_t{1} << (cycle % 64); }

 private:
  struct Block {
    std::uint64_t id = 0;    // cycle / 64 of the cycles this block describes
    std::uint64_t busy = 0;  // bit i: cycle id * 64 + i is taken
  };
  // The block of cycles id * 64 .. id * 64 + 63 (recycling one wholly in the past).
  Block& block(std::uint64_t id, std::uint64_t now) {
    for (;;) {
      Block& b = blocks_[id & (blocks_.size() - 1)];
      if (b.id == id) return b;
      if (b.busy != 0 && b.id + 1 > now / 64) {  // still live: make room and try again
        grow();
        continue;
      }
      b.id = id;
      b.busy = 0;
      return b;
    }
  }
  void grow() {
    std::vector<Block> old = std::move(blocks_);
    blocks_.assign(old.size() * 2, Block{});
    for (const Block& b : old)
      if (b.busy != 0) blocks_[b.id & (blocks_.size() - 1)] = b;
  }
  std::vector<Block> blocks_;
};

}  // namespace tigris::hw
