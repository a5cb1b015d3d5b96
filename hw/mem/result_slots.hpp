// The Result Buffer's per-query slots for NN/kNN: a count word, then up to k neighbours kept in
// the canonical (dist2, index) order of sw_ref/arith.hpp. Radius search keeps no slot: each hit
// is streamed out. The RU's PI stage and the PE's insert stage both update a slot through this
// view of the Result Buffer's DMI memory.
#pragma once

#include <cstdint>
#include <cstring>

#include "sw_ref/arith.hpp"

namespace tigris::hw {

class ResultSlots {
 public:
  static constexpr std::uint64_t kHeaderBytes = sizeof(Neighbor);  // the count, padded to a neighbour
  static std::uint64_t slot_bytes(std::uint32_t k) { return kHeaderBytes + sizeof(Neighbor) * std::uint64_t{k}; }

  ResultSlots() = default;
  ResultSlots(std::uint8_t* base, std::uint32_t k) : base_(base), k_(k) {}

  void clear(std::uint32_t slot) { set_count(slot, 0); }
  std::uint32_t count(std::uint32_t slot) const {
    std::uint32_t c;
    std::memcpy(&c, at(slot), 4);
    return c;
  }
  const Neighbor* entries(std::uint32_t slot) const {
    return reinterpret_cast<const Neighbor*>(at(slot) + kHeaderBytes);
  }
  // The pruning bound: the k-th best dist2, +inf while fewer than k are held.
  float bound(std::uint32_t slot) const {
    const std::uint32_t c = count(slot);
    return c < k_ ? kInfinity : entries(slot)[c - 1].dist2;
  }
  // Inserts n if it is among the k best so far (insertion sort); returns whether it was.
  bool insert(std::uint32_t slot, Neighbor n) {
    Neighbor* e = reinterpret_cast<Neighbor*>(at(slot) + kHeaderBytes);
    const std::uint32_t c = count(slot);
    if (c == k_ && !closer(n, e[c - 1])) return false;
    std::uint32_t pos = c < k_ ? c : k_ - 1;
    while (pos > 0 && closer(n, e[pos - 1])) {
      e[pos] = e[pos - 1];
      --pos;
    }
    e[pos] = n;
    if (c < k_) set_count(slot, c + 1);
    return true;
  }

 private:
  std::uint8_t* at(std::uint32_t slot) const { return base_ + slot * slot_bytes(k_); }
  void set_count(std::uint32_t slot, std::uint32_t c) { std::memcpy(at(slot), &c, 4); }
  std::uint8_t* base_ = nullptr;
  std::uint32_t k_ = 1;
};

}  // namespace tigris::hw
