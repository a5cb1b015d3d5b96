// Which cycles one SRAM bank is busy in, over a sliding window. Work items reserve their
// accesses when they start, some of them cycles ahead (a walk's later nodes, a stream's later
// words), so a single next-free time would make an access that comes later in simulation but
// earlier in cycles wait behind them. The calendar finds the first free cycle at or after the
// one asked for instead. Reservations more than the window ahead of older ones are not expected.
#pragma once

#include <cstdint>
#include <vector>

namespace tigris::hw {

class BankCalendar {
 public:
  explicit BankCalendar(std::size_t blocks = 256) : blocks_(blocks) {}  // 256 x 64 cycles

  void clear() { blocks_.assign(blocks_.size(), Block{}); }

  // Marks the first free cycle at or after `cycle` busy and returns it.
  std::uint64_t reserve(std::uint64_t cycle) {
    for (;;) {
      Block& b = blocks_[(cycle / 64) % blocks_.size()];
      const std::uint64_t id = cycle / 64;
      if (b.id != id) {
        if (b.id > id) return cycle;  // far in the past: the window moved on; nothing to book
        b.id = id;
        b.busy = 0;
      }
      const std::uint64_t free = ~b.busy >> (cycle % 64);
      if (free != 0) {
        cycle += static_cast<std::uint64_t>(__builtin_ctzll(free));
        b.busy |= std::uint64_t{1} << (cycle % 64);
        return cycle;
      }
      cycle = (id + 1) * 64;  // this block is full from here on
    }
  }

 private:
  struct Block {
    std::uint64_t id = 0;    // cycle / 64 of the cycles this block describes
    std::uint64_t busy = 0;  // bit i: cycle id * 64 + i is taken
  };
  std::vector<Block> blocks_;
};

}  // namespace tigris::hw
