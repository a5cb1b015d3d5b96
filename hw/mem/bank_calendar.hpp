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

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace tigris::hw {

class BankCalendar {
 public:
  explicit BankCalendar(std::uint32_t banks = 1) : banks_(banks) { clear(); }

  // Forgets every booking.
  void clear() {
    last_id_ = kNoRow;
    rows_.assign(kRows, Row{});
    busy_.assign(std::size_t{kRows} * banks_, 0);
    runs_.assign(banks_, Run{});
  }
  // The fast path of reserve(): books `cycle` in `bank` if the row looked up last holds that
  // cycle and the bank is free in it; false if reserve() must look further.
  bool try_book(std::uint32_t bank, std::uint64_t cycle) {
    if (cycle / 64 != last_id_) return false;
    std::uint64_t& w = last_bits_[bank];
    const std::uint64_t bit = std::uint64_t{1} << (cycle % 64);
    if (w & bit) return false;
    w |= bit;
    return true;
  }
  // Marks `bank`'s first free cycle at or after `cycle` busy and returns it; `now` is the
  // current cycle (rows wholly before it are free to reuse).
  std::uint64_t reserve(std::uint32_t bank, std::uint64_t cycle, std::uint64_t now) {
    std::uint64_t& first = word(bank, cycle / 64, now);  // most often free: book it at once
    const std::uint64_t bit = std::uint64_t{1} << (cycle % 64);
    if (!(first & bit)) {
      first |= bit;
      return cycle;
    }
    return reserve_later(bank, cycle, now);
  }
  // Books one word in each of `count` (<= banks) banks from `bank` on (wrapping), each at its
  // first free cycle at or after `cycle`; returns the cycle after the last one booked. What
  // `count` reserve() calls do, with the row looked up once while the banks are free.
  // `critical` gets the bank served last (the first bank when none waited).
  std::uint64_t reserve_span(std::uint32_t bank, std::uint32_t count, std::uint64_t cycle, std::uint64_t now,
                             std::uint32_t& critical) {
    critical = bank;
    const std::uint64_t bit = std::uint64_t{1} << (cycle % 64);
    std::uint64_t* row = &word(bank, cycle / 64, now) - bank;
    // The common case, all of them free at `cycle`: two runs of neighbouring words (the span
    // may wrap past the last bank), tested and booked in loops the compiler vectorizes.
    const std::uint32_t head = std::min(count, banks_ - bank), tail = count - head;
    std::uint64_t busy = 0;
    for (std::uint32_t i = 0; i < head; ++i) busy |= row[bank + i];
    for (std::uint32_t i = 0; i < tail; ++i) busy |= row[i];
    if (!(busy & bit)) {
      for (std::uint32_t i = 0; i < head; ++i) row[bank + i] |= bit;
      for (std::uint32_t i = 0; i < tail; ++i) row[i] |= bit;
      return cycle + 1;
    }
    std::uint64_t finish = cycle + 1;
    for (std::uint32_t i = 0; i < count; ++i, bank = bank + 1 == banks_ ? 0 : bank + 1) {
      if (!(row[bank] & bit)) {
        row[bank] |= bit;
        continue;
      }
      const std::uint64_t generation = generation_;
      const std::uint64_t served = reserve_later(bank, cycle, now) + 1;
      if (served > finish) finish = served, critical = bank;
      if (generation != generation_) row = &word(bank, cycle / 64, now) - bank;  // the ring grew: rows moved
    }
    return finish;
  }
  // Books `bank`'s first `m` (> 0) free cycles at or after `cycle` and returns the last: what m
  // reserve() calls, each from the cycle after the previous one, book; a row at a time.
  std::uint64_t reserve_n(std::uint32_t bank, std::uint64_t cycle, std::uint64_t m, std::uint64_t now) {
    Run& run = runs_[bank];
    const std::uint64_t asked = cycle;
    if (run.from <= cycle && cycle < run.to) cycle = run.to;
    std::uint64_t last = cycle;
    for (;;) {
      std::uint64_t& busy = word(bank, cycle / 64, now);
      std::uint64_t free = ~busy & (~std::uint64_t{0} << (cycle % 64));
      const std::uint64_t base = cycle / 64 * 64;
      cycle = base + 64;
      if (free == 0) continue;
      const std::uint64_t avail = popcount(free);
      if (avail < m) {
        busy |= free;
        m -= avail;
        continue;
      }
      std::uint64_t take = 0;
      for (; m > 0; --m) {  // the lowest m free cycles of this row
        const std::uint64_t low = free & (~free + 1);
        take |= low;
        free ^= low;
      }
      busy |= take;
      last = base + 63 - static_cast<std::uint64_t>(__builtin_clzll(take));
      break;
    }
    run.note(asked, last + 1);  // [asked, last] is now all booked
    return last;
  }
  // `bank`'s first free cycle at or after `cycle`, not booked.
  std::uint64_t next_free(std::uint32_t bank, std::uint64_t cycle, std::uint64_t now) {
    Run& run = runs_[bank];
    const std::uint64_t asked = cycle;
    if (run.from <= cycle && cycle < run.to) cycle = run.to;
    for (;;) {
      const std::uint64_t free = ~peek(bank, cycle / 64, now) >> (cycle % 64);
      if (free != 0) {
        cycle += static_cast<std::uint64_t>(__builtin_ctzll(free));
        break;
      }
      cycle = (cycle / 64 + 1) * 64;
    }
    run.note(asked, cycle);  // [asked, cycle) is all busy
    return cycle;
  }
  void book(std::uint32_t bank, std::uint64_t cycle, std::uint64_t now) {
    word(bank, cycle / 64, now) |= std::uint64_t{1} << (cycle % 64);
    if (cycle == runs_[bank].to) ++runs_[bank].to;
  }

 private:
  // reserve() when `cycle` itself is booked: the first free cycle after it. A bank that falls
  // behind books at the end of its run, in a row of its own: the bank's own cached row (not
  // the shared last row, which the other banks' accesses at the current cycle keep).
  std::uint64_t reserve_later(std::uint32_t bank, std::uint64_t cycle, std::uint64_t now) {
    Run& run = runs_[bank];
    // Most often the cycle after the run is free, in the bank's cached row.
    if (run.from <= cycle && cycle < run.to && run.row_id == run.to / 64) {
      const std::uint64_t bit = std::uint64_t{1} << (run.to % 64);
      if (!(*run.word & bit)) {
        *run.word |= bit;
        return run.to++;
      }
    }
    return reserve_after(bank, cycle, now);
  }
  __attribute__((noinline)) std::uint64_t reserve_after(std::uint32_t bank, std::uint64_t cycle, std::uint64_t now) {
    Run& run = runs_[bank];
    const std::uint64_t asked = cycle;
    if (run.from <= cycle && cycle < run.to) cycle = run.to;
    for (;;) {  // every row passed over is full (so already claimed); the last one is booked in
      std::uint64_t& busy = bank_word(run, bank, cycle / 64, now);
      const std::uint64_t free = ~busy >> (cycle % 64);
      if (free != 0) {
        cycle += static_cast<std::uint64_t>(__builtin_ctzll(free));
        busy |= std::uint64_t{1} << (cycle % 64);
        break;
      }
      cycle = (cycle / 64 + 1) * 64;
    }
    run.note(asked, cycle + 1);  // [asked, cycle] is now all booked
    return cycle;
  }
  // Portable (no -mpopcnt: the builtin would be a libgcc call).
  static std::uint64_t popcount(std::uint64_t x) {
    x = x - ((x >> 1) & 0x5555555555555555ULL);
    x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fULL;
    return (x * 0x0101010101010101ULL) >> 56;
  }
  static constexpr std::uint32_t kRows = 64;  // a power of two, doubled as needed
  struct Row {
    std::uint64_t id = 0;  // cycle / 64 of the cycles this row describes
    bool used = false;     // some bank has a booking in it
  };
  // `bank`'s busy bits for cycles id * 64 .. id * 64 + 63, without claiming a row for them.
  std::uint64_t peek(std::uint32_t bank, std::uint64_t id, std::uint64_t now) {
    if (id == last_id_) return last_bits_[bank];
    for (;;) {
      const std::size_t r = static_cast<std::size_t>(id & (rows_.size() - 1));
      const Row& row = rows_[r];
      if (row.id == id) return busy_[r * banks_ + bank];
      if (!row.used || row.id + 1 <= now / 64) return 0;  // a free or reusable row: nothing booked
      grow();
    }
  }
  // The same, to book in (recycling a row wholly in the past). The last row looked up is kept:
  // one work item's accesses mostly fall in the same 64 cycles.
  std::uint64_t& word(std::uint32_t bank, std::uint64_t id, std::uint64_t now) {
    if (id != last_id_) {
      const std::size_t r = lookup(id, now);  // (may grow the ring: the data pointer after it)
      last_id_ = id, last_bits_ = busy_.data() + r * banks_;
    }
    return last_bits_[bank];
  }
  // The ring index of row `id`, claimed (recycling a row wholly before `now`, or growing).
  __attribute__((noinline)) std::size_t lookup(std::uint64_t id, std::uint64_t now) {
    for (;;) {
      const std::size_t r = static_cast<std::size_t>(id & (rows_.size() - 1));
      Row& row = rows_[r];
      std::uint64_t* bits = busy_.data() + r * banks_;
      if (row.id != id) {
        if (row.used && row.id + 1 > now / 64) {  // still live: make room and try again
          grow();
          continue;
        }
        if (row.used) {  // recycled: it describes other cycles now, so the caches of it go
          std::fill(bits, bits + banks_, 0);
          if (bits == last_bits_) last_id_ = kNoRow;
          for (Run& run : runs_)
            if (run.row == r) run.row_id = kNoRow;
        }
        row.id = id;
      }
      row.used = true;
      return r;
    }
  }
  void grow() {
    last_id_ = kNoRow;
    ++generation_;
    for (Run& run : runs_) run.row_id = kNoRow;  // rows move
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
  static constexpr std::uint64_t kNoRow = ~std::uint64_t{0};
  std::uint32_t banks_;
  std::uint64_t last_id_ = kNoRow;      // the row word() looked up last ...
  std::uint64_t* last_bits_ = nullptr;  // ... and its busy bits
  std::uint64_t generation_ = 0;        // how often the ring has grown (rows moved)
  std::vector<Row> rows_;
  std::vector<std::uint64_t> busy_;  // rows_.size() x banks_
  // Per bank, cycles known to be all booked, so a search skips a long backlog at once (a bank
  // that falls behind by thousands of cycles would otherwise be rescanned row by row by every
  // access). Bookings are never taken back at or after the current cycle, so a run stays true.
  struct Run {
    std::uint64_t from = 0, to = 0;
    std::uint64_t row_id = kNoRow;  // the bank's cached row: its id, ...
    std::size_t row = 0;            // ... its place in the ring ...
    std::uint64_t* word = nullptr;  // ... and the bank's busy bits in it
    // [a, b) is all busy: joined to the run when they touch, else kept if it reaches further.
    void note(std::uint64_t a, std::uint64_t b) {
      if (a <= to && from <= b) {
        from = std::min(from, a);
        to = std::max(to, b);
      } else if (b > to) {
        from = a;
        to = b;
      }
    }
  };
  std::vector<Run> runs_;

  // `bank`'s word of row `id` through the bank's cached row (a row's cache is dropped when the
  // row is recycled or the ring grows).
  std::uint64_t& bank_word(Run& run, std::uint32_t bank, std::uint64_t id, std::uint64_t now) {
    if (run.row_id != id) {
      const std::size_t r = lookup(id, now);  // (may grow the ring, dropping every cache)
      run.row_id = id, run.row = r, run.word = busy_.data() + r * banks_ + bank;
    }
    return *run.word;
  }
};

}  // namespace tigris::hw
