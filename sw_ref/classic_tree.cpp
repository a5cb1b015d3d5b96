#include "classic_tree.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace tigris {

namespace {

struct ClassicBuilder {
  const PointCloud& cloud;
  ClassicTree& tree;
  std::vector<std::uint32_t> perm;

  // Tight box of perm[lo, hi): KdTreeH stores the same box (computeBoundingBox, kdtree.h:669-670).
  void bounds(std::size_t lo, std::size_t hi, Point3& mn, Point3& mx) const {
    mn = mx = cloud[perm[lo]];
    for (std::size_t i = lo + 1; i < hi; ++i) {
      const Point3& p = cloud[perm[i]];
      mn.x = std::min(mn.x, p.x), mx.x = std::max(mx.x, p.x);
      mn.y = std::min(mn.y, p.y), mx.y = std::max(mx.y, p.y);
      mn.z = std::min(mn.z, p.z), mx.z = std::max(mx.z, p.z);
    }
  }

  // Returns the new node's id. Recursion depth is the tree depth, about log2(n).
  std::uint32_t build(std::size_t lo, std::size_t hi, int depth) {
    const auto id = static_cast<std::uint32_t>(tree.nodes.size());
    tree.nodes.emplace_back();
    Point3 mn, mx;
    bounds(lo, hi, mn, mx);
    tree.nodes[id].lo = mn;
    tree.nodes[id].hi = mx;
    tree.depth = std::max(tree.depth, depth);
    const std::size_t n = hi - lo;
    if (n <= tree.leaf_max) {
      // Ascending index inside a leaf: nth_element's arrangement must not show in the image.
      std::sort(perm.begin() + lo, perm.begin() + hi);
      ClassicNode& leaf = tree.nodes[id];
      leaf.leaf = true;
      leaf.a = static_cast<std::uint32_t>(lo);
      leaf.b = static_cast<std::uint32_t>(hi);
      ++tree.num_leaves;
      return id;
    }
    // Widest extent of the box, ties x, then y, then z (KdTreeH findSplitDim, kdtree.h:823-840).
    const float ex = mx.x - mn.x, ey = mx.y - mn.y, ez = mx.z - mn.z;
    int axis = 0;
    float best = ex;
    if (ey > best) axis = 1, best = ey;
    if (ez > best) axis = 2;
    // Left child: the first ceil(n/2) points in (coordinate, index) order, i.e. up to and
    // including the lower median (KdTreeH's findMedian rank, kdtree.h:797). A strict total order,
    // so the halves as sets do not depend on nth_element; both halves are non-empty for n >= 2.
    const std::size_t left_n = (n + 1) / 2;
    const auto nth = perm.begin() + static_cast<std::ptrdiff_t>(lo + left_n - 1);
    std::nth_element(perm.begin() + lo, nth, perm.begin() + hi, [&](std::uint32_t p, std::uint32_t q) {
      const float cp = cloud[p][axis], cq = cloud[q][axis];
      return cp < cq || (cp == cq && p < q);
    });
    const float split = cloud[*nth][axis];
    const std::uint32_t left = build(lo, lo + left_n, depth + 1);
    const std::uint32_t right = build(lo + left_n, hi, depth + 1);
    ClassicNode& node = tree.nodes[id];  // re-fetched: the recursion grew the vector
    node.axis = static_cast<std::uint8_t>(axis);
    node.split = split;
    node.a = left;
    node.b = right;
    return id;
  }
};

// Squared distance from q to the box, in the order and precision of dist2(): each axis gap is
// rounded the way q - p would be for the nearest p in the box, and rounding is monotone, so the
// result never exceeds dist2(q, p) for a point p in the box. Pruning with it is therefore exact.
inline float box_dist2(const Point3& q, const ClassicNode& n) {
  const auto gap = [](float v, float lo, float hi) { return v < lo ? v - lo : (v > hi ? v - hi : 0.0f); };
  const float dx = gap(q.x, n.lo.x, n.hi.x);
  const float dy = gap(q.y, n.lo.y, n.hi.y);
  const float dz = gap(q.z, n.lo.z, n.hi.z);
  return ((dx * dx) + (dy * dy)) + (dz * dz);
}

// NN and kNN: the k best in canonical (dist2, index) order; the bound is the k-th's dist2.
struct KBest {
  std::vector<Neighbor> list;
  std::size_t k;
  explicit KBest(std::size_t k_) : k(k_) { list.reserve(k); }
  float bound() const { return list.size() < k ? kInfinity : list.back().dist2; }
  void offer(float d, std::uint32_t i) { offer_k_best(list, k, Neighbor{i, d}); }
  void emit(Results& r, std::uint32_t) {
    r.append_query(list.data(), list.data() + list.size());
    list.clear();
  }
};

// Radius: every point with dist2 <= r2 (the numeric contract), sorted, trimmed to max_nn.
struct InRadius {
  std::vector<Neighbor> hits;
  float r2;
  explicit InRadius(float r) : r2(square(r)) {}
  float bound() const { return r2; }
  void offer(float d, std::uint32_t i) {
    if (d <= r2) hits.push_back({i, d});
  }
  void emit(Results& r, std::uint32_t max_nn) {
    std::sort(hits.begin(), hits.end(), Closer{});
    if (max_nn > 0 && hits.size() > max_nn) hits.resize(max_nn);
    r.append_query(hits.data(), hits.data() + hits.size());
    hits.clear();
  }
};

template <class Collector>
void run_classic(const ClassicTree& t, const PointCloud& queries, const SearchParams& p, Collector c,
                 ClassicOutput& out) {
  std::vector<std::uint32_t> stack;
  stack.reserve(static_cast<std::size_t>(t.depth) + 1);
  for (std::size_t qi = 0; qi < queries.size(); ++qi) {
    const Point3& q = queries[qi];
    ClassicCounts& w = out.per_query[qi];
    // KdTreeH traverse_tree (kdtree.h:176-196): down to a leaf by the split, the far child pushed;
    // `q > split` goes right, so a query on the plane goes left with the split point.
    const auto descend_and_scan = [&](std::uint32_t node) {
      while (!t.nodes[node].leaf) {
        const ClassicNode& n = t.nodes[node];
        const bool right = q[n.axis] > n.split;
        stack.push_back(right ? n.a : n.b);
        node = right ? n.b : n.a;
      }
      const ClassicNode& leaf = t.nodes[node];
      ++w.leaves;
      w.dist += leaf.b - leaf.a;  // one distance computation per leaf point, as KdTreeH counts
      for (std::uint32_t pos = leaf.a; pos < leaf.b; ++pos) c.offer(dist2(q, t.points[pos]), t.index[pos]);
    };
    // KdTreeH nearestKSearch / radiusSearch (kdtree.h:260-296, 345-378): the first leaf is
    // scanned unconditionally; then the stack is popped (deepest far child first), each popped
    // subtree's box is tested against the current bound, and a survivor is descended (without
    // testing the boxes on that path) to one leaf, pushing its own far children.
    stack.clear();
    descend_and_scan(0);
    while (!stack.empty()) {
      const std::uint32_t node = stack.back();
      stack.pop_back();
      ++w.box_tests;
      if (box_dist2(q, t.nodes[node]) > c.bound()) continue;
      ++w.backtracks;
      descend_and_scan(node);
    }
    c.emit(out.results, p.mode == Mode::Radius ? p.max_nn : 0);
    out.dist += w.dist;
    out.leaves += w.leaves;
    out.box_tests += w.box_tests;
    out.backtracks += w.backtracks;
  }
}

}  // namespace

ClassicTree build_classic_tree(const PointCloud& cloud, std::uint32_t leaf_max) {
  validate_cloud(cloud, "tree cloud");
  if (leaf_max < 1) throw std::invalid_argument("classic tree: leaf_max must be >= 1");
  if (cloud.size() >= kNoPoint) throw std::invalid_argument("cloud too large for 32-bit indices");
  ClassicTree tree;
  tree.leaf_max = leaf_max;
  // A child of a split node holds at least max(1, leaf_max / 2) points: that bounds the leaves.
  tree.nodes.reserve(2 * (cloud.size() / std::max<std::size_t>(1, leaf_max / 2)) + 1);
  ClassicBuilder b{cloud, tree, std::vector<std::uint32_t>(cloud.size())};
  std::iota(b.perm.begin(), b.perm.end(), 0u);
  b.build(0, cloud.size(), 0);
  tree.index = std::move(b.perm);
  tree.points.reserve(tree.index.size());
  for (std::uint32_t i : tree.index) tree.points.push_back(cloud[i]);
  return tree;
}

std::uint32_t classic_leaf_max_for_height(std::size_t num_points, int top_height) {
  if (top_height < 0 || top_height > 62) throw std::invalid_argument("top height out of range");
  const std::uint64_t d = std::uint64_t{1} << top_height;
  return static_cast<std::uint32_t>(std::max<std::uint64_t>(1, (num_points + d - 1) / d));
}

ClassicOutput classic_search(const ClassicTree& tree, const PointCloud& queries, const SearchParams& params) {
  validate(params);
  if (params.approximate)
    throw std::invalid_argument("classic tree: approximate (leader/follower) search is not defined on it");
  validate_cloud(queries, "queries");
  if (queries.size() >= kNoPoint) throw std::invalid_argument("too many queries");
  ClassicOutput out;
  out.per_query.resize(queries.size());
  out.results.offset.reserve(queries.size() + 1);
  if (params.mode == Mode::Radius)
    run_classic(tree, queries, params, InRadius(params.radius), out);
  else
    run_classic(tree, queries, params, KBest(static_cast<std::size_t>(params.effective_k())), out);
  return out;
}

}  // namespace tigris
