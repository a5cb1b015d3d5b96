// A global-buffer SRAM (Point, Query, Query Stack or Result Buffer): word-interleaved banks,
// a port limit and a read latency. Each bank keeps a calendar of its busy cycles, so accesses
// to a busy bank wait for its next free cycle (contention); nothing runs per cycle.
//
// Reached over TLM-2.0: host READ/WRITE transactions copy data (and are timed as bursts);
// units use DMI for data and TLM_IGNORE_COMMAND + AccessProfile for timing.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <tlm_utils/multi_passthrough_target_socket.h>
#include <systemc>
#include <tlm>

#include "bank_calendar.hpp"
#include "fast_divider.hpp"
#include "hw/clock.hpp"
#include "hw/config.hpp"
#include "hw/energy_meter.hpp"
#include "port_calendar.hpp"
#include "zeroed_bytes.hpp"
#ifdef TIGRIS_CHECK_SRAM
#include "sram_reference.hpp"
#endif
#include "hw/stall_injector.hpp"
#include "hw/stats.hpp"
#include "tlm/access_profile.hpp"

namespace tigris::hw {

class BankedSram final : public sc_core::sc_module, public tlm_if::TimingTarget {
 public:
  tlm_utils::multi_passthrough_target_socket<BankedSram> socket;

  // Its accesses are charged to `meter` at the energy table's SRAM price for its bytes and banks.
  // `stall`: random stall injection on its grants (off by default).
  BankedSram(sc_core::sc_module_name name, const SramConfig& config, Clock clock, EnergyMeter& meter,
             const AcceleratorConfig::Stall& stall = {});

  std::uint64_t size() const { return data_.size(); }
  // reads/writes (bank words), read_bytes/write_bytes (payload), conflict_cycles (lost to busy
  // banks or ports); reset at START with the whole tree, so the host's loads are not counted.
  StatGroup& stats() { return stats_; }

  // A job starts: the banks forget their bookings (all in the past: the host's loads).
  void start() {
    banks_.clear();
    ports_.clear();
#ifdef TIGRIS_CHECK_SRAM
    reference_.clear();
#endif
    stall_.start();
  }
  // Charges an access starting at cycle `start`; returns the cycle its data is complete.
  std::uint64_t charge(std::uint64_t start, const tlm_if::AccessProfile& access) override;
  // Inline, and the class final: a unit's port that knows this buffer (BufferPort::request's
  // template) calls it directly, and a one-word access whose bank is free costs the caller's loop
  // a few instructions.
  std::uint64_t charge_one(std::uint64_t start, std::uint64_t byte, std::uint32_t bytes, bool write) override {
    std::uint32_t bank;
    return in_one_word(byte, bytes, bank) ? charge_word(start, bank, bytes, write)
                                          : charge_one_profiled(start, byte, bytes, write);
  }

 private:
  std::uint64_t charge_in_order(std::uint64_t start, const tlm_if::AccessProfile& access);
  // Whether an access of `bytes` (> 0) at `byte` lies within one word (and ports never bind):
  // then `bank` is its word's bank. Never under TIGRIS_CHECK_SRAM (its check takes a profile).
  bool in_one_word(std::uint64_t byte, std::uint64_t bytes, std::uint32_t& bank) const {
#ifdef TIGRIS_CHECK_SRAM
    return false;
#endif
    if (word_in_row_) {
      bank = static_cast<std::uint32_t>((byte >> word_shift_) & bank_mask_);
      return bytes > 0 && (byte & (word_bytes_ - 1)) + bytes <= word_bytes_;
    }
    if (ports_bind_ || bytes == 0) return false;
    const std::uint64_t word = word_index(byte);
    bank = bank_of(word);
    return word_index(byte + bytes - 1) == word;
  }
  // Books one word in `bank` at `start` or its first free cycle after; what charge() and
  // charge_in_order() do for a one-word access, without a profile.
  std::uint64_t charge_word(std::uint64_t start, std::uint32_t bank, std::uint64_t bytes, bool write) {
    const std::uint64_t served = banks_.try_book(bank, start) ? start : reserve_when_busy(bank, start);
    ++bank_accesses_[bank];
    if (served != start) {
      bank_conflicts_[bank] += served - start;
      conflict_cycles_ += served - start;
    }
    count(write, 1, bytes);
    return served + 1 + static_cast<std::uint64_t>(config_.latency_cycles) + stall_.draw();
  }
  // charge_word()'s bank busy at `start` (or not in the calendar's current row): its first free
  // cycle, booked. Out of line, as the next one: their frames would slow the short path down.
  __attribute__((noinline)) std::uint64_t reserve_when_busy(std::uint32_t bank, std::uint64_t start) {
    return banks_.reserve(bank, start, std::min(start, clock_.now()));
  }
  // charge_one() beyond one word, as a one-access pipeline profile.
  __attribute__((noinline)) std::uint64_t charge_one_profiled(std::uint64_t start, std::uint64_t byte,
                                                              std::uint32_t bytes, bool write);
  // Books one word access in `bank` at the first cycle >= `cycle` when the bank and a port are
  // free (ports shared by every unit; only tracked when they can bind: fewer ports than banks).
  std::uint64_t reserve(std::uint32_t bank, std::uint64_t cycle, std::uint64_t now) {
    if (!ports_bind_) return banks_.reserve(bank, cycle, now);
    for (;;) {
      cycle = banks_.next_free(bank, cycle, now);
      if (ports_.has_room(cycle, now)) break;
      ++cycle;
    }
    banks_.book(bank, cycle, now);
    ports_.take(cycle, now);
    return cycle;
  }
  // Books the `words` words from word `first` (each bank's share in its first free cycles at
  // or after `cycle`, one after another) and counts them per bank; returns the cycle after the
  // last one booked; `critical` gets the bank served last.
  std::uint64_t reserve_words(std::uint64_t first, std::uint64_t words, std::uint64_t cycle, std::uint64_t now,
                              std::uint32_t& critical);
  void count(bool write, std::uint64_t words, std::uint64_t bytes) {
    (write ? writes_ : reads_) += words;
    (write ? write_bytes_ : read_bytes_) += bytes;
    (write ? write_energy_ : read_energy_) += bytes;
  }
  // With TIGRIS_CHECK_SRAM: the naive model books the access too and must agree on `served`, the
  // cycle after its last word; else nothing.
  void check(std::uint64_t start, const tlm_if::AccessProfile& access, std::uint64_t now, std::uint64_t served);
  // The words an access of `bytes` at `first_byte` touches: (first word, how many).
  std::pair<std::uint64_t, std::uint64_t> words_of(std::uint64_t first_byte, std::uint64_t bytes) const {
    if (bytes == 0) return {word_index(first_byte), 0};
    const std::uint64_t first = word_index(first_byte);
    return {first, word_index(first_byte + bytes - 1) - first + 1};
  }
  // Word and bank arithmetic with shifts and masks when the sizes are powers of two (the
  // defaults), else by multiplications (hw/mem/fast_divider.hpp).
  std::uint64_t word_index(std::uint64_t byte) const {
    return word_shift_ >= 0 ? byte >> word_shift_ : word_div_(byte);
  }
  std::uint32_t bank_of(std::uint64_t word) const {
    return static_cast<std::uint32_t>(bank_mask_ ? word & bank_mask_ : word - bank_div_(word) * num_banks_);
  }
  void b_transport(int id, tlm::tlm_generic_payload& trans, sc_core::sc_time& delay);
  bool get_direct_mem_ptr(int id, tlm::tlm_generic_payload& trans, tlm::tlm_dmi& dmi);
  unsigned int transport_dbg(int id, tlm::tlm_generic_payload& trans);

  SramConfig config_;
  Clock clock_;
  ZeroedBytes data_;  // zero until written (no set-up cost for what a job leaves untouched)
  std::uint64_t word_bytes_, num_banks_;
  int word_shift_;           // log2(word_bytes_), or -1
  std::uint64_t bank_mask_;  // num_banks_ - 1 for a power of two, else 0
  FastDivider word_div_, bank_div_;
  std::uint64_t lanes_;  // words served a cycle at best: min(banks, ports)
  int lanes_shift_;      // log2(lanes_), or -1
  BankCalendar banks_;
  bool ports_bind_;
  // Words and banks (two or more) are powers of two and ports never bind: a pipeline access
  // within one word finds its bank with a shift and a mask (charge_in_order's short path).
  bool word_in_row_;
  PortCalendar ports_;
#ifdef TIGRIS_CHECK_SRAM
  SramReference reference_;
#endif
  StatGroup stats_;
  // Words count accesses (`word_bytes` each: an access of a few bytes is one word).
  Counter reads_{stats_, "reads", "count", "words read"};
  Counter writes_{stats_, "writes", "count",
                  "words written during the job (the host's loads before START are not counted)"};
  Counter read_bytes_{stats_, "read_bytes", "bytes", "bytes read"};
  Counter write_bytes_{stats_, "write_bytes", "bytes", "bytes written during the job"};
  Counter conflict_cycles_{stats_, "conflict_cycles", "cycles",
                           "cycles accesses waited for a busy bank or port beyond the ideal"};
  // Per bank (bank i holds words i, i + banks, ...): where the traffic and the waiting are.
  CounterArray bank_accesses_{stats_, "banks.accesses", "count",
                              "words read or written in each bank, in bank order (sums to reads + writes)",
                              static_cast<std::size_t>(config_.banks)};
  CounterArray bank_conflicts_{stats_, "banks.conflict_cycles", "cycles",
                               "each access's conflict cycles charged to the bank served last, the one it waited "
                               "for, in bank order (sums to conflict_cycles)",
                               static_cast<std::size_t>(config_.banks)};
  Counter& read_energy_;
  Counter& write_energy_;
  StallInjector stall_;
};

}  // namespace tigris::hw
