#include <catch2/catch.hpp>

#include <algorithm>
#include <utility>
#include <vector>

#include "sw_ref/brute_force.hpp"
#include "sw_ref/search.hpp"
#include "test_util.hpp"
#include "workloads/synthetic.hpp"

using namespace tigris;
using namespace tigris::test;

namespace {

// A second, recursive statement of docs/model.md's search semantics (exact search), written independently
// of the iterative engine, to check visit counts as well as results.
struct RecursiveRef {
  const KdTree& t;
  const SearchParams& p;
  Point3 q;
  std::vector<Neighbor> found;  // NN/kNN: the k best so far, in canonical order
  QueryVisits v;

  bool nonempty(std::uint32_t node) const {
    if (node < t.top.size()) return !t.top[node].empty();
    return t.leaf_size(node - static_cast<std::uint32_t>(t.top.size())) > 0;
  }
  float bound() const {
    if (p.mode == Mode::Radius) return square(p.radius);
    return found.size() < static_cast<std::size_t>(p.effective_k()) ? kInfinity : found.back().dist2;
  }
  void offer(float d, std::uint32_t i) {
    // A radius search's bound is fixed: what it finds does not steer the walk, and the results
    // are checked against brute force, so only NN/kNN keep their k best here.
    if (p.mode == Mode::Radius) return;
    found.insert(std::upper_bound(found.begin(), found.end(), Neighbor{i, d}, closer), Neighbor{i, d});
    if (found.size() > static_cast<std::size_t>(p.effective_k())) found.pop_back();
  }
  void visit(std::uint32_t node) {
    if (node >= t.top.size()) {
      const std::uint32_t leaf = node - static_cast<std::uint32_t>(t.top.size());
      ++v.leaf_visits;
      for (std::uint32_t pos = t.leaf_begin[leaf]; pos < t.leaf_begin[leaf + 1]; ++pos) {
        ++v.leaf_points;
        offer(dist2(q, t.leaf_points[pos]), t.leaf_index[pos]);
      }
      return;
    }
    const TopNode& n = t.top[node];
    ++v.top;
    offer(dist2(q, n.point), n.index);
    const bool left = q[n.axis] < n.point[n.axis];
    const std::uint32_t near = 2 * node + (left ? 1 : 2), far = 2 * node + (left ? 2 : 1);
    if (nonempty(near)) visit(near);
    if (nonempty(far)) {
      const float d = q[n.axis] - n.point[n.axis];
      if (d * d > bound())
        ++v.pruned;
      else
        visit(far);
    }
  }
};

// `oracle` is brute_force(cloud, queries, p): it does not depend on the tree, so callers compute
// it once per mode for all the trees they check.
void check_against_references(const PointCloud& cloud, const PointCloud& queries, const KdTree& tree,
                              const SearchParams& p, const Results& oracle) {
  const SearchOutput out = search(tree, queries, p);
  const auto diff = first_difference(oracle, out.results);
  if (diff) FAIL("mismatch against brute force: " << *diff);
  for (std::uint32_t qi = 0; qi < queries.size(); ++qi) {
    RecursiveRef ref{tree, p, queries[qi], {}, {}};
    if (tree.top.empty() ? tree.leaf_size(0) > 0 : !tree.top[0].empty()) ref.visit(0);
    // One check per query, not six assertions: Catch's bookkeeping dominated this loop.
    const QueryVisits& got = out.per_query[qi];
    if (got.top != ref.v.top || got.pruned != ref.v.pruned || got.leaf_points != ref.v.leaf_points ||
        got.leaf_visits != ref.v.leaf_visits || got.follower_points != 0 || got.leader_checks != 0)
      FAIL("query " << qi << " visits (top, pruned, leaf points, leaf visits, follower points, leader checks): "
                    << got.top << ", " << got.pruned << ", " << got.leaf_points << ", " << got.leaf_visits << ", "
                    << got.follower_points << ", " << got.leader_checks << "; the recursive reference: " << ref.v.top
                    << ", " << ref.v.pruned << ", " << ref.v.leaf_points << ", " << ref.v.leaf_visits << ", 0, 0");
  }
  // Every query reaches every point once at h = 0; nothing is pruned there.
  if (tree.top_height == 0) REQUIRE(out.visits.leaf_points == cloud.size() * queries.size());
  REQUIRE(out.schedule.size() == out.visits.leaf_visits);
}

std::vector<SearchParams> all_modes() {
  std::vector<SearchParams> v;
  SearchParams p;
  p.mode = Mode::NN;
  v.push_back(p);
  p.mode = Mode::KNN;
  for (int k : {1, 4, 10}) p.k = k, v.push_back(p);
  p.mode = Mode::Radius;
  for (float r : {0.3f, 1.0f, 2.5f}) p.radius = r, v.push_back(p);
  p.max_nn = 3;
  v.push_back(p);
  return v;
}

}  // namespace

TEST_CASE("exact search equals brute force and the recursive reference on random clouds", "[search]") {
  const auto kind =
      GENERATE(CloudKind::Uniform, CloudKind::Duplicates, CloudKind::AllEqual, CloudKind::Collinear, CloudKind::Grid);
  const std::size_t n = GENERATE(1u, 2u, 5u, 64u, 500u, 5000u);
  const std::uint64_t seed = GENERATE(1u, 2u);
  const PointCloud cloud = make_cloud(kind, n, seed * 1000 + n);
  const PointCloud queries = make_queries(cloud, n >= 5000 ? 150 : 60, seed);
  const int full = full_height_for(n);
  std::vector<std::pair<SplitRule, KdTree>> trees;
  for (int h : {0, 1, 3, 10, full})
    for (auto rule : {SplitRule::WidestExtent, SplitRule::RoundRobin})
      if (h <= full) trees.emplace_back(rule, build_kdtree(cloud, h, rule));
  for (const SearchParams& p : all_modes()) {
    const Results oracle = brute_force(cloud, queries, p);
    for (const auto& [rule, tree] : trees) {
      INFO(name(kind) << " n=" << n << " seed=" << seed << " h=" << tree.top_height << " split=" << to_string(rule)
                      << " mode=" << to_string(p.mode) << " k=" << p.k << " r=" << p.radius << " max_nn=" << p.max_nn);
      check_against_references(cloud, queries, tree, p, oracle);
    }
  }
}

TEST_CASE("exact search on the synthetic LiDAR pair equals brute force", "[search][synthetic]") {
  const SyntheticPair pair = make_synthetic_pair();
  PointCloud queries;  // a spread-out subset keeps brute force fast
  for (std::size_t i = 0; i < pair.frame1.size(); i += 211) queries.push_back(pair.frame1[i]);
  const int full = full_height_for(pair.frame0.size());
  std::vector<KdTree> trees;
  for (int h : {0, 1, 3, 10, full}) trees.push_back(build_kdtree(pair.frame0, h));
  SearchParams nn, knn, r030, r075;
  knn.mode = Mode::KNN, knn.k = 10;
  r030.mode = r075.mode = Mode::Radius;
  r030.radius = 0.30f, r075.radius = 0.75f;
  for (const SearchParams& p : {nn, knn, r030, r075}) {
    const Results oracle = brute_force(pair.frame0, queries, p);
    for (const KdTree& tree : trees) {
      INFO("h=" << tree.top_height << " mode=" << to_string(p.mode) << " r=" << p.radius);
      check_against_references(pair.frame0, queries, tree, p, oracle);
    }
  }
}

TEST_CASE("two-stage tree at full height is the canonical tree: no leaf scans, same results", "[search]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 3000, 11);
  const PointCloud queries = make_queries(cloud, 300, 11);
  const KdTree canon = build_kdtree(cloud, -1);
  const KdTree deep = build_kdtree(cloud, canon.full_height - 1);
  SearchParams p;
  const SearchOutput a = search(canon, queries, p), b = search(deep, queries, p);
  CHECK(a.visits.leaf_points == 0);
  CHECK(a.schedule.empty());
  CHECK_FALSE(first_difference(a.results, b.results));
  // One level less of top-tree turns the deepest nodes into one-point leaf sets, offered in
  // the same order: each such top visit becomes a leaf-point visit, all else is unchanged.
  CHECK(a.visits.top == b.visits.top + b.visits.leaf_points);
  CHECK(a.visits.pruned == b.visits.pruned);
  CHECK(b.visits.leaf_points > 0);
}

TEST_CASE("search parameters are validated", "[search]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 50, 3);
  const KdTree tree = build_kdtree(cloud, 2);
  SearchParams p;
  p.mode = Mode::KNN, p.k = 0;
  CHECK_THROWS_WITH(search(tree, cloud, p), Catch::Contains("k must be >= 1"));
  p.mode = Mode::Radius, p.radius = 0.0f;
  CHECK_THROWS_WITH(search(tree, cloud, p), Catch::Contains("radius"));
  p.radius = -1.0f;
  CHECK_THROWS_AS(search(tree, cloud, p), std::invalid_argument);
  p.radius = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(search(tree, cloud, p), std::invalid_argument);
  p.radius = 1.0f;
  PointCloud bad = cloud;
  bad[7].z = std::numeric_limits<float>::infinity();
  CHECK_THROWS_WITH(search(tree, bad, p), Catch::Contains("point 7"));
  CHECK_THROWS_AS(search(tree, PointCloud{}, p), InputError);
  CHECK_THROWS_AS(parse_mode("nearest"), std::invalid_argument);
}
