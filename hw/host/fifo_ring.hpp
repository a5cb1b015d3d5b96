// A FIFO in one array that grows by doubling (a host data structure, not hardware). The FE
// Query Queue holds up to every query in flight: in a std::deque its tokens sit in scattered
// 512-byte blocks the host cache has long dropped by the time they are dispatched, while one
// array is read in order, which the host's hardware prefetcher follows.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace tigris::hw {

template <typename T>
class FifoRing {
 public:
  void clear() { head_ = size_ = 0; }
  // Room for `n` entries without growing (call before the run, with the queue's bound).
  void reserve(std::size_t n) {
    std::size_t c = items_.empty() ? 16 : items_.size();
    while (c < n) c *= 2;
    if (c > items_.size()) regrow(c);
  }
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  T& front() { return items_[head_]; }
  const T& operator[](std::size_t i) const { return items_[(head_ + i) & (items_.size() - 1)]; }
  void push_back(const T& t) {
    if (size_ == items_.size()) regrow(items_.empty() ? 16 : 2 * items_.size());
    const std::size_t mask = items_.size() - 1;
    items_[(head_ + size_++) & mask] = t;
    __builtin_prefetch(&items_[(head_ + size_ + 8) & mask], 1);  // last touched a whole lap ago
  }
  void pop_front() {
    head_ = (head_ + 1) & (items_.size() - 1);
    --size_;
  }

 private:
  void regrow(std::size_t capacity) {  // a power of two, so an index wraps with a mask
    std::vector<T> grown(capacity);
    for (std::size_t i = 0; i < size_; ++i) grown[i] = std::move(items_[(head_ + i) & (items_.size() - 1)]);
    items_ = std::move(grown);
    head_ = 0;
  }
  std::vector<T> items_;
  std::size_t head_ = 0, size_ = 0;
};

}  // namespace tigris::hw
