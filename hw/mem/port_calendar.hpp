// How many accesses a buffer's ports carry in each cycle, across every unit that uses the
// buffer: at most `ports` a cycle (docs/model.md, arbitration). Kept only when the ports can bind,
// i.e. fewer ports than banks (each bank already serves one access a cycle). Same layout as
// BankCalendar: a ring of 64-cycle blocks that doubles when a live block would be overwritten.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace tigris::hw {

class PortCalendar {
 public:
  explicit PortCalendar(std::uint32_t ports) : ports_(ports), blocks_(64) {}

  bool has_room(std::uint64_t cycle, std::uint64_t now) { return block(cycle / 64, now).used[cycle % 64] < ports_; }
  void take(std::uint64_t cycle, std::uint64_t now) {
    Block& b = block(cycle / 64, now);
    ++b.used[cycle % 64];
    b.live = true;
  }
  void clear() { blocks_.assign(64, Block{}); }

 private:
  struct Block {
    std::uint64_t id = 0;
    bool live = false;
    std::array<std::uint32_t, 64> used{};
  };
  Block& block(std::uint64_t id, std::uint64_t now) {
    for (;;) {
      Block& b = blocks_[id & (blocks_.size() - 1)];
      if (b.id == id) return b;
      if (b.live && b.id + 1 > now / 64) {
        grow();
        continue;
      }
      b = Block{};
      b.id = id;
      return b;
    }
  }
  void grow() {
    std::vector<Block> old = std::move(blocks_);
    blocks_.assign(old.size() * 2, Block{});
    for (const Block& b : old)
      if (b.live) blocks_[b.id & (blocks_.size() - 1)] = b;
  }
  std::uint32_t ports_;
  std::vector<Block> blocks_;
};

}  // namespace tigris::hw
