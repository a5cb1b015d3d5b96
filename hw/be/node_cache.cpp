#include "node_cache.hpp"

namespace tigris::hw {

bool NodeCache::lookup(std::uint32_t leaf, std::uint64_t bytes) {
  if (!enabled()) return false;
  const auto it = where_.find(leaf);
  if (it != where_.end()) {
    lru_.splice(lru_.begin(), lru_, it->second);
    ++stats_.hits;
    stats_.read_bytes += bytes;
    return true;
  }
  ++stats_.misses;
  if (bytes > capacity_) return false;
  while (used_ + bytes > capacity_) {
    used_ -= lru_.back().second;
    where_.erase(lru_.back().first);
    lru_.pop_back();
  }
  lru_.emplace_front(leaf, bytes);
  where_[leaf] = lru_.begin();
  used_ += bytes;
  stats_.fill_bytes += bytes;
  return false;
}

}  // namespace tigris::hw
