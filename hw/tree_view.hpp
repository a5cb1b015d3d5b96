// The tree image in the Point Buffer (tlm/tree_image.hpp) as a unit reads it through its DMI
// pointer: top-tree nodes, leaf sets and the leaf directory.
#pragma once

#include <cstdint>

#include "job.hpp"

namespace tigris::hw {

class TreeView {
 public:
  TreeView() = default;
  TreeView(const std::uint8_t* point_buffer, const JobDescriptor& job)
      : entries_(reinterpret_cast<const tlm_if::PointEntry*>(point_buffer)),
        dir_(reinterpret_cast<const tlm_if::LeafDirEntry*>(point_buffer + job.leaf_dir_offset)),
        dir_offset_(job.leaf_dir_offset), top_nodes_(job.num_top_nodes), leaves_(job.num_leaves) {}

  std::uint32_t num_top_nodes() const { return top_nodes_; }
  const tlm_if::PointEntry& node(std::uint32_t n) const { return entries_[n]; }
  // Leaf set `leaf`: entries [begin, end) after the top-tree.
  std::uint32_t leaf_begin(std::uint32_t leaf) const { return dir_[leaf]; }
  std::uint32_t leaf_end(std::uint32_t leaf) const { return dir_[leaf + 1]; }
  std::uint32_t leaf_size(std::uint32_t leaf) const { return leaf_end(leaf) - leaf_begin(leaf); }
  const tlm_if::PointEntry* leaf_entries() const { return entries_ + top_nodes_; }
  bool leaf_nonempty(std::uint32_t leaf) const { return leaves_ != 0 && leaf_size(leaf) > 0; }
  bool node_nonempty(std::uint32_t n) const {
    return n < top_nodes_ ? entries_[n].tag != tlm_if::kEmptyTag : leaf_nonempty(n - top_nodes_);
  }
  // Byte addresses in the Point Buffer, for the timing accesses.
  std::uint64_t node_address(std::uint32_t n) const { return std::uint64_t{n} * sizeof(tlm_if::PointEntry); }
  std::uint64_t leaf_address(std::uint32_t leaf) const {
    return (std::uint64_t{top_nodes_} + leaf_begin(leaf)) * sizeof(tlm_if::PointEntry);
  }
  std::uint64_t dir_address(std::uint32_t leaf) const {
    return dir_offset_ + std::uint64_t{leaf} * sizeof(tlm_if::LeafDirEntry);
  }

 private:
  const tlm_if::PointEntry* entries_ = nullptr;
  const tlm_if::LeafDirEntry* dir_ = nullptr;
  std::uint64_t dir_offset_ = 0;
  std::uint32_t top_nodes_ = 0, leaves_ = 0;
};

}  // namespace tigris::hw
