// The tree image in the Point Buffer: what the host writes and the accelerator walks.
//
//   entries [0, 2^h - 1)        top-tree nodes in heap order, 16 bytes each (PointEntry);
//                               tag = index | axis << 30, or kEmptyTag for an empty subtree
//   entries [2^h - 1, ...)      leaf sets, left to right, 16 bytes each; tag = point index
//   leaf directory (optional)   uint32 begin[2^h + 1], entry offsets of the leaf sets relative
//                               to the first leaf entry; absent when every leaf set is empty
//                               (the canonical tree), which keeps Acc-KD within the buffer
#pragma once

#include <cstdint>
#include <vector>

#include "sw_ref/kdtree.hpp"

namespace tigris::tlm_if {

struct PointEntry {
  float x, y, z;
  std::uint32_t tag;
};
static_assert(sizeof(PointEntry) == 16, "point entries are 16 bytes");

using LeafDirEntry = std::uint32_t;  // one leaf directory entry (an entry offset)
constexpr std::uint32_t kEmptyTag = 0xFFFFFFFFu;
constexpr std::uint32_t kIndexMask = 0x3FFFFFFFu;
constexpr int kAxisShift = 30;

struct TreeImage {
  std::vector<std::uint8_t> bytes;  // Point Buffer contents
  std::uint32_t num_top_nodes = 0;
  std::uint32_t num_leaves = 0;  // 0: no leaf directory
  std::uint32_t leaf_dir_offset = 0;
  int top_height = 0;
};

// Serialises a tree; throws std::invalid_argument for clouds of 2^30 points or more.
TreeImage encode_tree_image(const KdTree& tree);

}  // namespace tigris::tlm_if
