// The classic KD-tree in the authors' convention: a golden-model option used
// only to count work for the paper's redundancy figure (section 4.1), never a tree image the
// accelerator loads.
//
// It follows KdTreeH of the authors' code (horizon-research/PointCloud-pipeline,
// kdtree_module/include/kdtree.h), which differs from our canonical tree (kdtree.hpp) in what
// the paper's "35x NN / 3x radius" depends on:
//   - points live only in leaves (at most `leaf_max` each); inner nodes hold no point;
//   - every node keeps the tight bounding box of its points, and a subtree is pruned by the
//     distance from the query to that box, not to the split plane;
//   - cost is the number of query-to-point distance computations (the authors'
//     approx_nn_ops_num_ / approx_radius_ops_num_), which only leaf scans perform.
// With leaf_max = 1 this is "the classic KD-tree with leaf size one"; with leaf_max ~ 32 it is
// what the authors' code runs as the two-stage tree (ICP_Max_Leaf_Size: 32).
//
// Deliberate departures from KdTreeH, so that results are exact and the build deterministic:
//   - split at a position, not a value: the node's points ordered by (coordinate, index), the
//     left child takes the first ceil(n/2). KdTreeH's value split gives the left child
//     floor(n/2)+1 points and never terminates for max_leaf_size 0 (two points: both go left);
//   - a box is pruned when its distance exceeds the bound (KdTreeH: when it reaches it), and
//     a radius hit is dist2 <= r2 (KdTreeH: dist < r): the numeric contract of arith.hpp and the
//     canonical tie rule (dist2, index) of brute_force(), so results equal brute force exactly.
//     The counts differ from KdTreeH's only when a box distance ties the bound exactly.
#pragma once

#include <cstdint>
#include <vector>

#include "cloud.hpp"
#include "results.hpp"
#include "search.hpp"

namespace tigris {

struct ClassicNode {
  Point3 lo, hi;               // tight bounding box of the node's points
  float split = 0.0f;          // inner: the largest `axis` coordinate among the left child's points
  std::uint32_t a = 0, b = 0;  // inner: left and right child node ids; leaf: positions [a, b)
  std::uint8_t axis = 0;       // inner: split axis, 0 x, 1 y, 2 z
  bool leaf = false;
};

struct ClassicTree {
  std::uint32_t leaf_max = 1;        // a node of at most leaf_max points is a leaf
  std::vector<ClassicNode> nodes;    // node 0 is the root; preorder
  std::vector<std::uint32_t> index;  // leaf positions -> input index (ascending inside a leaf)
  std::vector<Point3> points;        // the points in leaf-position order
  std::uint32_t num_leaves = 0;
  int depth = 0;  // levels below the root of the deepest leaf
};

// Builds the classic tree over `cloud` (validated; InputError for a bad cloud). leaf_max >= 1,
// else std::invalid_argument. KdTreeH's max_leaf_size m corresponds to leaf_max m + 1.
ClassicTree build_classic_tree(const PointCloud& cloud, std::uint32_t leaf_max = 1);

// ceil(n / 2^h): the leaf_max whose leaves are those of a two-stage tree of top height h (the
// same number of halvings), so both trees can be compared at the same leaf-set size.
std::uint32_t classic_leaf_max_for_height(std::size_t num_points, int top_height);

// One query's work.
struct ClassicCounts {
  std::uint32_t dist = 0;        // query-to-point distance computations (the authors' ops counter)
  std::uint32_t leaves = 0;      // leaves scanned
  std::uint32_t box_tests = 0;   // backtracked subtrees whose box was tested against the bound
  std::uint32_t backtracks = 0;  // of those, the ones searched (KdTreeH's back_track)
};

struct ClassicOutput {
  Results results;  // canonical order, equal to brute_force()
  std::vector<ClassicCounts> per_query;
  std::uint64_t dist = 0, leaves = 0, box_tests = 0, backtracks = 0;  // sums over the queries
};

// Exact NN, kNN or radius search of every query (params.mode, k, radius, max_nn; max_nn trims
// only what is returned). Approximate search is not defined on this tree: std::invalid_argument.
ClassicOutput classic_search(const ClassicTree& tree, const PointCloud& queries, const SearchParams& params);

}  // namespace tigris
