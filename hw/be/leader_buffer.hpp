// The Leader Buffer of one Search Unit (paper section 5.3 "Approximate Search";
// docs/model.md): for every leaf the SU owns (leaf id mod SUs), up to leader.capacity_per_leaf
// leaders in arrival order, 12 bytes each (the leader's point), and where each leader's local
// result list lives. Lists are written into this SU's equal share of the Result Buffer's
// leader-list area (16-byte entries: x, y, z, index, as in the Point Buffer), bump-allocated
// within a job; a list that no longer fits is kept in DRAM (a documented spill: its write and
// every follower's read cross the write-back channel), or, with result_buffer.leader_lists =
// resident (the paper's accounting), stays in the Result Buffer: its accesses are charged at
// the share's banks, its address wrapped into the share (the paper bounds the lists by nothing).
#pragma once

#include <cstdint>
#include <vector>

#include "hw/config.hpp"
#include "hw/energy_meter.hpp"
#include "hw/job.hpp"
#include "hw/stats.hpp"
#include "sw_ref/arith.hpp"
#include "tlm/tree_image.hpp"

namespace tigris::hw {

class LeaderBuffer {
 public:
  static constexpr std::uint64_t kLeaderBytes = 12;  // x, y, z as float32
  static constexpr std::uint64_t kListEntryBytes = sizeof(tlm_if::PointEntry);

  struct Leader {
    Point3 point;
    std::uint64_t list_address = 0;   // byte address in the Result Buffer, or in the overflow store
    std::uint32_t list_length = 0;    // entries
    bool overflowed = false;          // beyond its SU's share: in the overflow store (DRAM, or resident)
    std::uint64_t ready = 0;          // cycle the list is written and followers may read it
    bool pending = false;             // first_leaf, wait: reserved at its check, still searching
    std::vector<QueryToken> waiters;  // wait: followers parked until its list is written
  };

  LeaderBuffer(std::uint32_t su, const AcceleratorConfig& config, EnergyMeter& meter);

  // A job starts: no leaders; `result_buffer` is the Result Buffer's storage (DMI).
  void start(const JobDescriptor& job, std::uint8_t* result_buffer);
  const std::vector<Leader>& leaders(std::uint32_t leaf) const { return leaves_[slot(leaf)]; }
  bool full(std::uint32_t leaf) const { return leaders(leaf).size() >= capacity_; }
  // Whether a list's accesses cross the write-back channel (spilled), not the Result Buffer's banks.
  bool in_dram(const Leader& l) const { return l.overflowed && !resident_; }
  // Where the Result Buffer's banks see a list's first byte (a resident overflow list wraps).
  std::uint64_t bank_address(const Leader& l) const {
    return l.overflowed ? area_base_ + (area_bytes_ ? l.list_address % area_bytes_ : 0) : l.list_address;
  }
  // The check stream reads `entries` leaders of one leaf.
  void read(std::uint64_t entries) {
    read_bytes_ += entries * kLeaderBytes;
    read_energy_ += entries * kLeaderBytes;
  }
  // Appends a leader at `leaf` (not full) with its local list; returns its index. The list's
  // storage is allocated and written now; the caller times the write and sets `ready`.
  std::size_t append(std::uint32_t leaf, const Point3& point, const std::vector<tlm_if::PointEntry>& list);
  // first_leaf, wait: a leader's entry from its check (its point), and its list when its search
  // has finished (stored as append() stores it).
  std::size_t reserve(std::uint32_t leaf, const Point3& point);
  void fill(std::uint32_t leaf, std::size_t index, const std::vector<tlm_if::PointEntry>& list);
  Leader& leader(std::uint32_t leaf, std::size_t index) { return leaves_[slot(leaf)][index]; }
  const tlm_if::PointEntry* list(const Leader& l) const;
  StatGroup& stats() { return stats_; }

 private:
  std::size_t slot(std::uint32_t leaf) const { return leaf / sus_; }
  void store_list(Leader& l, const std::vector<tlm_if::PointEntry>& list);

  std::uint32_t su_, sus_;
  std::uint32_t capacity_;
  bool resident_;  // result_buffer.leader_lists: lists beyond the share stay in the Result Buffer
  std::vector<std::vector<Leader>> leaves_;
  std::uint8_t* area_ = nullptr;  // this SU's share of the leader-list area
  std::uint64_t area_base_ = 0, area_bytes_ = 0, area_used_ = 0;
  std::vector<tlm_if::PointEntry> overflow_;  // lists beyond the share (DRAM, or resident)
  StatGroup stats_;
  Counter read_bytes_{stats_, "read_bytes", "bytes",
                      "Leader Buffer bytes read by the Leader Checks (12 bytes a leader)"};
  Counter write_bytes_{stats_, "write_bytes", "bytes", "Leader Buffer bytes written (new leaders' points)"};
  Counter list_bytes_{stats_, "list_bytes", "bytes",
                      "leaders' local result lists written (16-byte entries), wherever they live"};
  Counter dram_lists_{stats_, "dram_lists", "count",
                      "lists that found their SU's share of the Result Buffer full and were kept in DRAM"};
  Counter resident_overflow_{stats_, "resident_overflow_lists", "count",
                             "lists that found their SU's share full and stayed in the Result Buffer "
                             "(result_buffer.leader_lists = resident)"};
  Counter max_leaders_{stats_, "max_leaders_per_leaf", "count", "most leaders any leaf held", Counter::Merge::Max};
  Counter& read_energy_;
  Counter& write_energy_;
};

}  // namespace tigris::hw
