// The canonical and the two-stage KD-tree of docs/model.md (trees), as one tree image type.
//
// Heap numbering covers the whole tree: top node i has children 2i+1 and 2i+2; with top height
// h the top-tree is nodes 0 .. 2^h-2 and the top-tree leaves (leaf sets) are nodes 2^h-1 ..
// 2^(h+1)-2, numbered leaf 0 .. 2^h-1 left to right. The canonical tree is the two-stage tree
// at full height: every leaf set is then empty.
//
// This header (with arith.hpp) is the tree image the hardware model loads; it holds no search.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cloud.hpp"

namespace tigris {

enum class SplitRule { WidestExtent, RoundRobin };

SplitRule parse_split_rule(const std::string& name);  // "widest" | "round-robin"
const char* to_string(SplitRule rule);

constexpr std::uint32_t kNoPoint = 0xFFFFFFFFu;

struct TopNode {
  Point3 point;                    // the node's split point
  std::uint32_t index = kNoPoint;  // its input index; kNoPoint: empty subtree
  std::uint8_t axis = 0;           // split axis: 0 x, 1 y, 2 z
  bool empty() const { return index == kNoPoint; }
};

struct KdTree {
  int top_height = 0;   // h: levels of the top-tree
  int full_height = 0;  // ceil(log2(n+1)): the canonical tree's height
  SplitRule split = SplitRule::WidestExtent;
  std::size_t num_points = 0;

  std::vector<TopNode> top;  // 2^h - 1 nodes, heap order
  // Leaf set j is leaf_index/leaf_points[leaf_begin[j] .. leaf_begin[j+1]), ascending index.
  std::vector<std::uint32_t> leaf_begin;  // 2^h + 1 offsets
  std::vector<std::uint32_t> leaf_index;
  std::vector<Point3> leaf_points;

  std::uint32_t num_leaves() const { return static_cast<std::uint32_t>(leaf_begin.size() - 1); }
  std::uint32_t first_leaf_node() const { return static_cast<std::uint32_t>(top.size()); }
  std::uint32_t leaf_size(std::uint32_t leaf) const { return leaf_begin[leaf + 1] - leaf_begin[leaf]; }
  bool is_canonical() const { return top_height == full_height; }
};

// ceil(log2(n+1)): the height of the canonical tree over n points.
int full_height_for(std::size_t num_points);

// Builds the two-stage tree of top height h (0 <= h <= full height; h = -1 means full).
// Throws std::invalid_argument for an impossible height, InputError for a bad cloud.
KdTree build_kdtree(const PointCloud& cloud, int top_height, SplitRule split = SplitRule::WidestExtent);

}  // namespace tigris
