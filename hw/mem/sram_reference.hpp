// The naive model of a BankedSram's bookings, for the debug build option TIGRIS_CHECK_SRAM:
// every bank a plain set of its busy cycles, the ports a count per cycle, each word booked one at
// a time at the first cycle its bank (and, when ports can bind, a port) is free. BankedSram's
// calendars, rows, fast paths and multi-word bookings are for speed only; with the option on, it
// recomputes every access here and stops the simulation at the first one that books otherwise.
// The order is the contract's: a burst books each bank's share one word after another, bank by
// bank from the first word's; a pipeline access's words all from its issue cycle.
#pragma once

#include <algorithm>
#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "tlm/access_profile.hpp"

namespace tigris::hw {

class SramReference {
 public:
  SramReference(std::uint64_t word_bytes, std::uint64_t banks, std::uint64_t ports)
      : word_bytes_(word_bytes), banks_(banks), ports_(ports), busy_(banks) {}

  void clear() {
    for (auto& b : busy_) b.clear();
    used_.clear();
  }
  // The cycle after the last word of `a` starting at `start` is served (for a burst: at least
  // `start`; for a pipeline: after its last access), booking every word. `now`: no later access
  // asks for an earlier cycle, so older bookings are dropped now and then.
  std::uint64_t charge(std::uint64_t start, const tlm_if::AccessProfile& a, std::uint64_t now) {
    if (++calls_ % 4096 == 0) forget_before(now);
    if (a.pipeline) {
      std::uint64_t stall = 0, last = start;
      for (std::uint32_t i = 0; i < a.pipeline_count; ++i) {
        const tlm_if::PipelineAccess& p = a.pipeline[i];
        const std::uint64_t t = start + p.issue_offset + stall;
        std::uint64_t served = t;
        if (p.bytes > 0)
          for (std::uint64_t w = p.byte / word_bytes_; w <= (p.byte + p.bytes - 1) / word_bytes_; ++w)
            served = std::max(served, reserve(w % banks_, t));
        stall += served - t;
        last = served + 1;
      }
      return last;
    }
    std::uint64_t finish = start;
    if (a.scatter)
      for (std::uint32_t i = 0; i < a.scatter_count; ++i)
        finish = std::max(finish, burst(a.scatter[i], a.scatter_size, start));
    else
      finish = std::max(finish, burst(a.first_byte, a.bytes, start));
    return finish;
  }

 private:
  void forget_before(std::uint64_t now) {
    for (auto& b : busy_) b.erase(b.begin(), b.lower_bound(now));
    used_.erase(used_.begin(), used_.lower_bound(now));
  }
  std::uint64_t burst(std::uint64_t byte, std::uint64_t bytes, std::uint64_t start) {
    if (bytes == 0) return start;
    const std::uint64_t first = byte / word_bytes_, words = (byte + bytes - 1) / word_bytes_ - first + 1;
    std::uint64_t finish = start;
    for (std::uint64_t i = 0; i < std::min(words, banks_); ++i) {
      std::uint64_t t = start;
      for (std::uint64_t w = first + i; w < first + words; w += banks_) t = reserve((first + i) % banks_, t) + 1;
      finish = std::max(finish, t);
    }
    return finish;
  }
  std::uint64_t reserve(std::uint64_t bank, std::uint64_t cycle) {
    const bool ports_bind = ports_ < banks_;
    while (busy_[bank].count(cycle) || (ports_bind && used_[cycle] >= ports_)) ++cycle;
    busy_[bank].insert(cycle);
    if (ports_bind) ++used_[cycle];
    return cycle;
  }

  std::uint64_t word_bytes_, banks_, ports_, calls_ = 0;
  std::vector<std::set<std::uint64_t>> busy_;
  std::map<std::uint64_t, std::uint64_t> used_;
};

}  // namespace tigris::hw
