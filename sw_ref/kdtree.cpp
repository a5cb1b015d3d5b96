#include "kdtree.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace tigris {

SplitRule parse_split_rule(const std::string& name) {
  if (name == "widest") return SplitRule::WidestExtent;
  if (name == "round-robin") return SplitRule::RoundRobin;
  throw std::invalid_argument("unknown split axis rule '" + name + "' (use widest or round-robin)");
}

const char* to_string(SplitRule rule) { return rule == SplitRule::WidestExtent ? "widest" : "round-robin"; }

int full_height_for(std::size_t num_points) {
  int h = 0;
  while (num_points > 0) {  // H(n) = 1 + H(floor(n/2)), the left (larger) half
    num_points /= 2;
    ++h;
  }
  return h;
}

namespace {

struct Builder {
  const PointCloud& cloud;
  SplitRule split;
  int height;
  KdTree& tree;
  std::vector<std::uint32_t> perm;
  std::vector<std::uint32_t> leaf_lo, leaf_hi;  // each leaf's range of perm

  int choose_axis(std::size_t lo, std::size_t hi, int depth) const {
    if (split == SplitRule::RoundRobin) return depth % 3;
    Point3 mn = cloud[perm[lo]], mx = mn;
    for (std::size_t i = lo + 1; i < hi; ++i) {
      const Point3& p = cloud[perm[i]];
      mn.x = std::min(mn.x, p.x), mx.x = std::max(mx.x, p.x);
      mn.y = std::min(mn.y, p.y), mx.y = std::max(mx.y, p.y);
      mn.z = std::min(mn.z, p.z), mx.z = std::max(mx.z, p.z);
    }
    const float ex = mx.x - mn.x, ey = mx.y - mn.y, ez = mx.z - mn.z;
    int axis = 0;  // ties: x, then y, then z
    float best = ex;
    if (ey > best) axis = 1, best = ey;
    if (ez > best) axis = 2;
    return axis;
  }

  void build(std::uint32_t node, std::size_t lo, std::size_t hi, int depth) {
    if (depth == height) {
      const std::uint32_t leaf = node - static_cast<std::uint32_t>(tree.top.size());
      leaf_lo[leaf] = static_cast<std::uint32_t>(lo);
      leaf_hi[leaf] = static_cast<std::uint32_t>(hi);
      return;
    }
    if (lo == hi) return;  // empty subtree: nodes stay kNoPoint, leaf ranges stay empty
    const int axis = choose_axis(lo, hi, depth);
    const std::size_t mid = lo + (hi - lo) / 2;
    // Order by (coordinate on axis, index): a strict total order, so the median and the two
    // halves (as sets) do not depend on how nth_element permutes them.
    std::nth_element(perm.begin() + lo, perm.begin() + mid, perm.begin() + hi, [&](std::uint32_t a, std::uint32_t b) {
      const float ca = cloud[a][axis], cb = cloud[b][axis];
      return ca < cb || (ca == cb && a < b);
    });
    TopNode& n = tree.top[node];
    n.index = perm[mid];
    n.point = cloud[n.index];
    n.axis = static_cast<std::uint8_t>(axis);
    build(2 * node + 1, lo, mid, depth + 1);
    build(2 * node + 2, mid + 1, hi, depth + 1);
  }
};

}  // namespace

KdTree build_kdtree(const PointCloud& cloud, int top_height, SplitRule split) {
  validate_cloud(cloud, "tree cloud");
  if (cloud.size() >= kNoPoint) throw std::invalid_argument("cloud too large for 32-bit indices");
  const int full = full_height_for(cloud.size());
  if (top_height < 0) top_height = full;
  if (top_height > full)
    throw std::invalid_argument("top height " + std::to_string(top_height) + " exceeds the full height " +
                                std::to_string(full) + " of a " + std::to_string(cloud.size()) + "-point tree");
  KdTree tree;
  tree.top_height = top_height;
  tree.full_height = full;
  tree.split = split;
  tree.num_points = cloud.size();
  const std::size_t leaves = std::size_t{1} << top_height;
  tree.top.assign(leaves - 1, TopNode{});

  Builder b{cloud,
            split,
            top_height,
            tree,
            std::vector<std::uint32_t>(cloud.size()),
            std::vector<std::uint32_t>(leaves, 0),
            std::vector<std::uint32_t>(leaves, 0)};
  std::iota(b.perm.begin(), b.perm.end(), 0u);
  b.build(0, 0, cloud.size(), 0);

  // Leaf sets, left to right, each in ascending index order so the image is canonical.
  tree.leaf_begin.assign(leaves + 1, 0);
  tree.leaf_index.reserve(cloud.size());
  for (std::size_t j = 0; j < leaves; ++j) {
    tree.leaf_begin[j] = static_cast<std::uint32_t>(tree.leaf_index.size());
    const auto first = b.perm.begin() + b.leaf_lo[j], last = b.perm.begin() + b.leaf_hi[j];
    std::sort(first, last);
    tree.leaf_index.insert(tree.leaf_index.end(), first, last);
  }
  tree.leaf_begin[leaves] = static_cast<std::uint32_t>(tree.leaf_index.size());
  tree.leaf_points.reserve(tree.leaf_index.size());
  for (std::uint32_t i : tree.leaf_index) tree.leaf_points.push_back(cloud[i]);
  return tree;
}

}  // namespace tigris
