// The Result Buffer's per-query slots for NN/kNN: a count word, then up to k neighbours. While
// a query searches, its list is a max-heap in the canonical (dist2, index) order of
// sw_ref/arith.hpp (the worst held neighbour first: the pruning bound is one read, an insert
// O(log k), so a large k stays cheap); when it finishes, finish() sorts the list closest first.
// Radius search keeps no slot: each hit is streamed out. The RU's PI stage and the PE's insert
// stage both update a slot through this view of the Result Buffer's DMI memory.
#pragma once

#include <algorithm>
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
  float bound(std::uint32_t slot) const { return count(slot) < k_ ? kInfinity : entries(slot)[0].dist2; }
  // Inserts n if it is among the k best so far; returns whether it was.
  bool insert(std::uint32_t slot, Neighbor n) {
    Neighbor* e = mutable_entries(slot);
    const std::uint32_t c = count(slot);
    if (c < k_) {
      e[c] = n;
      std::push_heap(e, e + c + 1, Closer{});
      set_count(slot, c + 1);
      return true;
    }
    if (!closer(n, e[0])) return false;
    // n replaces the worst (the root) and sinks below every entry it is closer than (one pass,
    // where pop_heap then push_heap would make two; any heap gives the same bound and list).
    std::uint32_t i = 0;
    for (std::uint32_t child; (child = 2 * i + 1) < c; i = child) {
      if (child + 1 < c && closer(e[child], e[child + 1])) ++child;  // the worse child
      if (!closer(n, e[child])) break;
      e[i] = e[child];
    }
    e[i] = n;
    return true;
  }
  // Where a slot lives in host memory, for the host's cache hints (hw/host/scan_service.hpp).
  const void* address(std::uint32_t slot) const { return at(slot); }
  std::uint64_t bytes() const { return slot_bytes(k_); }
  // The query is done: its list in canonical order, closest first (entries() then reads it).
  void finish(std::uint32_t slot) {
    Neighbor* e = mutable_entries(slot);
    std::sort(e, e + count(slot), Closer{});  // (a total order: any sort gives the same list)
  }

 private:
  Neighbor* mutable_entries(std::uint32_t slot) { return reinterpret_cast<Neighbor*>(at(slot) + kHeaderBytes); }
  std::uint8_t* at(std::uint32_t slot) const { return base_ + slot * slot_bytes(k_); }
  void set_count(std::uint32_t slot, std::uint32_t c) { std::memcpy(at(slot), &c, 4); }
  std::uint8_t* base_ = nullptr;
  std::uint32_t k_ = 1;
};

}  // namespace tigris::hw
