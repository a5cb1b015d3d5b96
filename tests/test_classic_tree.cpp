// The authors' classic tree (sw_ref/classic_tree.hpp), the golden-model option that counts the
// paper's redundancy in the authors' convention: its answers equal brute force on
// the awkward clouds, its leaves respect leaf_max, and its cost counts are what it scanned.
#include <catch2/catch.hpp>

#include "sw_ref/brute_force.hpp"
#include "sw_ref/classic_tree.hpp"
#include "sw_ref/kdtree.hpp"
#include "test_util.hpp"

using namespace tigris;
using namespace tigris::test;

TEST_CASE("classic tree: answers equal brute force on random and degenerate clouds", "[classic]") {
  const auto kind = GENERATE(CloudKind::Uniform, CloudKind::Duplicates, CloudKind::AllEqual, CloudKind::Grid);
  const std::size_t n = GENERATE(1u, 2u, 64u, 3000u);
  const PointCloud cloud = make_cloud(kind, n, 7 * n + 1);
  const PointCloud queries = make_queries(cloud, 80, 3);
  SearchParams nn, knn, radius, trimmed;
  knn.mode = Mode::KNN, knn.k = 8;
  radius.mode = trimmed.mode = Mode::Radius;
  radius.radius = trimmed.radius = 1.0f;
  trimmed.max_nn = 5;
  for (std::uint32_t leaf_max : {1u, 2u, 3u, 33u, 5000u}) {
    const ClassicTree tree = build_classic_tree(cloud, leaf_max);
    std::uint32_t largest = 0, points = 0;
    for (const ClassicNode& node : tree.nodes)
      if (node.leaf) largest = std::max(largest, node.b - node.a), points += node.b - node.a;
    CHECK(points == n);
    CHECK(largest <= leaf_max);
    for (const SearchParams& p : {nn, knn, radius, trimmed}) {
      INFO("kind " << name(kind) << " n " << n << " leaf_max " << leaf_max << " mode " << to_string(p.mode));
      const ClassicOutput out = classic_search(tree, queries, p);
      const auto diff = first_difference(brute_force(cloud, queries, p), out.results);
      CHECK_FALSE(diff.has_value());
      // Every leaf scanned costs its points' distances; the first leaf is always scanned.
      std::uint64_t dist = 0;
      for (const ClassicCounts& c : out.per_query) {
        CHECK(c.leaves >= 1);
        CHECK(c.dist >= 1);
        CHECK(c.backtracks <= c.box_tests);
        dist += c.dist;
      }
      CHECK(dist == out.dist);
    }
  }
}

TEST_CASE("classic tree: larger leaves cost more distance computations (the redundancy)", "[classic]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 20000, 5);
  const PointCloud queries = make_queries(cloud, 500, 9);
  SearchParams nn;
  const ClassicOutput one = classic_search(build_classic_tree(cloud, 1), queries, nn);
  const ClassicOutput big = classic_search(build_classic_tree(cloud, 32), queries, nn);
  CHECK(big.dist > 4 * one.dist);  // a leaf of up to 32 points is scanned whole
  CHECK(classic_leaf_max_for_height(20000, 10) == 20);
  CHECK(classic_leaf_max_for_height(20000, 0) == 20000);
  CHECK_THROWS_AS(build_classic_tree(cloud, 0), std::invalid_argument);
  SearchParams approx;
  approx.approximate = true;
  approx.approx_thd = 1.2f;
  CHECK_THROWS_AS(classic_search(build_classic_tree(cloud, 8), queries, approx), std::invalid_argument);
}
