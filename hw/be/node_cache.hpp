// Node Cache (paper section 5.3): entries hold whole Node Sets, read as FIFOs; a lookup is by
// leaf id, replacement is least recently used. A Node Set larger than the cache bypasses it.
#pragma once

#include <cstdint>
#include <list>
#include <unordered_map>

#include "hw/stats.hpp"

namespace tigris::hw {

class NodeCache {
 public:
  explicit NodeCache(std::uint64_t bytes) : capacity_(bytes) {}

  void reset() {
    lru_.clear();
    where_.clear();
    used_ = 0;
    stats_ = {};
  }
  bool enabled() const { return capacity_ > 0; }
  // True on a hit; on a miss the Node Set is filled (evicting the least recently used).
  bool lookup(std::uint32_t leaf, std::uint64_t bytes);
  const NodeCacheStats& stats() const { return stats_; }

 private:
  std::uint64_t capacity_, used_ = 0;
  std::list<std::pair<std::uint32_t, std::uint64_t>> lru_;  // most recent first
  std::unordered_map<std::uint32_t, std::list<std::pair<std::uint32_t, std::uint64_t>>::iterator> where_;
  NodeCacheStats stats_;
};

}  // namespace tigris::hw
