// Which cycles each bank of one SRAM is busy in. Work items reserve their accesses when they
// start, some of them cycles ahead (a walk's later nodes, a stream's later words), so a single
// next-free time per bank would make an access that comes later in simulation but earlier in
// cycles wait behind them. The calendar finds a bank's first free cycle at or after the one
// asked for.
//
// Layout (for speed; it decides nothing): a ring of rows, each row the busy bits of 64 cycles
// for every bank side by side, so a burst over neighbouring banks touches neighbouring words.
// A row is recycled once its cycles are wholly before the current cycle; the ring doubles
// whenever a booking would overwrite a row that is still ahead of it.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

namespace tigris::hw {

class BankCalendar {
 public:
  explicit BankCalendar(std::uint32_t banks = 1) : banks_(banks) { clear(); }

  // Forgets every booking.
  void clear() {
    rows_.assign(kRows, Row{});
    busy_.assign(std::size_t{kRows} * banks_, 0);
  }
  // Marks `bank`'s first free cycle at or after `cycle` busy and returns it; `now` is the
  // current cycle (rows wholly before it are free to reuse).
  std::uint64_t reserve(std::uint32_t bank, std::uint64_t cycle, std::uint64_t now) {
    for (;;) {
      std::uint64_t& busy = word(bank, cycle / 64, now);
      const std::uint64_t free = ~busy >> (cycle % 64);
      if (free != 0) {
        cycle += static_cast<std::uint64_t>(__builtin_ctzll(free));
        busy |= std::uint64_t{1} << (cycle % 64);
        return cycle;
      }
      cycle = (cycle / 64 + 1) * 64;  // full from here to the row's end
    }
  }
  // `bank`'s first free cycle at or after `cycle`, not booked.
  std::uint64_t next_free(std::uint32_t bank, std::uint64_t cycle, std::uint64_t now) {
    for (;;) {
      const std::uint64_t free = ~peek(bank, cycle / 64, now) >> (cycle % 64);
      if (free != 0) return cycle + static_cast<std::uint64_t>(__builtin_ctzll(free));
      cycle = (cycle / 64 + 1) * 64;
    }
  }
  void book(std::uint32_t bank, std::uint64_t cycle, std::uint64_t now) {
    word(bank, cycle / 64, now) |= std::uint64_t{1} << (cycle % 64);
  }

 private:
  static constexpr std::uint32_t kRows = 64;  // a power of two, doubled as needed
  struct Row {
    std::uint64_t id = 0;  // cycle / 64 of the cycles this row describes
    bool used = false;     // some bank has a booking in it
  };
  // `bank`'s busy bits for cycles id * 64 .. id * 64 + 63, without claiming a row for them.
  std::uint64_t peek(std::uint32_t bank, std::uint64_t id, std::uint64_t now) {
    for (;;) {
      const std::size_t r = static_cast<std::size_t>(id & (rows_.size() - 1));
      const Row& row = rows_[r];
      if (row.id == id) return busy_[r * banks_ + bank];
      if (!row.used || row.id + 1 <= now / 64) return 0;  // a free or reusable row: nothing booked
      grow();
    }
  }
  // The same, to book in (recycling a row wholly in the past).
  std::uint64_t& word(std::uint32_t bank, std::uint64_t id, std::uint64_t now) {
    for (;;) {
      const std::size_t r = static_cast<std::size_t>(id & (rows_.size() - 1));
      Row& row = rows_[r];
      std::uint64_t* bits = busy_.data() + r * banks_;
      if (row.id != id) {
        if (row.used && row.id + 1 > now / 64) {  // still live: make room and try again
          grow();
          continue;
        }
        row.id = id;
        if (row.used) std::fill(bits, bits + banks_, 0);
      }
      row.used = true;
      return bits[bank];
    }
  }
  void grow() {
    std::vector<Row> old_rows = std::move(rows_);
    std::vector<std::uint64_t> old_busy = std::move(busy_);
    rows_.assign(old_rows.size() * 2, Row{});
    busy_.assign(rows_.size() * banks_, 0);
    for (std::size_t r = 0; r < old_rows.size(); ++r) {
      if (!old_rows[r].used) continue;
      const std::size_t to = static_cast<std::size_t>(old_rows[r].id & (rows_.size() - 1));
      rows_[to] = old_rows[r];
      std::copy(old_busy.begin() + r * banks_, old_busy.begin() + (r + 1) * banks_, busy_.begin() + to * banks_);
    }
  }
  std::uint32_t banks_;
  std::vector<Row> rows_;
  std::vector<std::uint64_t> busy_;  // rows_.size() x banks_
};

}  // namespace tigris::hw
