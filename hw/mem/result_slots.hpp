// The Result Buffer's per-query slots for NN/kNN: up to k (index, dist2) entries kept in
// (dist2, index) order, plus a count. Radius search keeps no slot: each hit is streamed out.
// The RU's PI stage and the PE's insert stage both update a slot through this view.
#pragma once

#include <cstdint>
#include <cstring>

#include "hw/job.hpp"

namespace tigris::hw {

class ResultSlots {
 public:
  struct Entry {
    std::uint32_t index;
    float dist2;
  };

  static std::uint64_t slot_bytes(std::uint32_t k) { return 8 + 8 * std::uint64_t{k}; }

  ResultSlots(std::uint8_t* base, std::uint32_t k) : base_(base), k_(k) {}

  void clear(std::uint32_t slot) { set_count(slot, 0); }
  std::uint32_t count(std::uint32_t slot) const {
    std::uint32_t c;
    std::memcpy(&c, at(slot), 4);
    return c;
  }
  const Entry* entries(std::uint32_t slot) const {
    return reinterpret_cast<const Entry*>(at(slot) + 8);
  }
  // The pruning bound: the k-th best dist2, +inf while fewer than k are held.
  float bound(std::uint32_t slot) const {
    const std::uint32_t c = count(slot);
    return c < k_ ? kInfinity : entries(slot)[c - 1].dist2;
  }
  // Inserts (index, d) if it is among the k best so far; returns whether it was.
  bool insert(std::uint32_t slot, std::uint32_t index, float d) {
    Entry* e = reinterpret_cast<Entry*>(at(slot) + 8);
    std::uint32_t c = count(slot);
    auto better = [](float da, std::uint32_t ia, const Entry& b) {
      return da < b.dist2 || (da == b.dist2 && ia < b.index);
    };
    if (c == k_ && !better(d, index, e[c - 1])) return false;
    std::uint32_t pos = c < k_ ? c : k_ - 1;  // shift worse entries down (insertion sort)
    while (pos > 0 && better(d, index, e[pos - 1])) {
      e[pos] = e[pos - 1];
      --pos;
    }
    e[pos] = {index, d};
    if (c < k_) set_count(slot, c + 1);
    return true;
  }

 private:
  std::uint8_t* at(std::uint32_t slot) const { return base_ + slot * slot_bytes(k_); }
  void set_count(std::uint32_t slot, std::uint32_t c) { std::memcpy(at(slot), &c, 4); }
  std::uint8_t* base_;
  std::uint32_t k_;
};

}  // namespace tigris::hw
