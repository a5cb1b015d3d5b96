// The DRAM region the result stream fills: bytes appended, read back by address. Kept in
// blocks, so a region of many megabytes grows without being copied (a vector doubling would
// copy it and touch twice its pages); blocks are kept for the next job.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

namespace tigris::hw {

class RecordRegion {
 public:
  void clear() { size_ = 0; }
  std::uint64_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  void append(const void* data, std::uint64_t n) {
    const auto* from = static_cast<const std::uint8_t*>(data);
    while (n > 0) {
      const std::uint64_t block = size_ / kBlock, at = size_ % kBlock;
      if (block == blocks_.size()) blocks_.emplace_back(new std::uint8_t[kBlock]);  // not zeroed: written first
      const std::uint64_t take = std::min(n, kBlock - at);
      std::memcpy(blocks_[block].get() + at, from, take);
      from += take, n -= take, size_ += take;
    }
  }
  // Copies [addr, addr + n) (within size()) to `to`.
  void read(std::uint64_t addr, void* to, std::uint64_t n) const {
    auto* out = static_cast<std::uint8_t*>(to);
    while (n > 0) {
      const std::uint64_t at = addr % kBlock, take = std::min(n, kBlock - at);
      std::memcpy(out, blocks_[addr / kBlock].get() + at, take);
      out += take, addr += take, n -= take;
    }
  }

 private:
  static constexpr std::uint64_t kBlock = std::uint64_t{8} << 20;
  std::vector<std::unique_ptr<std::uint8_t[]>> blocks_;
  std::uint64_t size_ = 0;
};

}  // namespace tigris::hw
