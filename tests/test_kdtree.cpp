#include <catch2/catch.hpp>

#include <algorithm>
#include <set>
#include <stdexcept>

#include "sw_ref/kdtree.hpp"
#include "test_util.hpp"

using namespace tigris;
using namespace tigris::test;

namespace {

// Order by (coordinate on axis, index): the tree's strict total order.
bool before(const PointCloud& c, std::uint32_t a, std::uint32_t b, int axis) {
  return c[a][axis] < c[b][axis] || (c[a][axis] == c[b][axis] && a < b);
}

// All point indices in the canonical subtree under heap node `node` of a full-height tree.
void collect(const KdTree& t, std::uint32_t node, std::vector<std::uint32_t>& out) {
  if (node >= t.top.size() || t.top[node].empty()) return;
  out.push_back(t.top[node].index);
  collect(t, 2 * node + 1, out);
  collect(t, 2 * node + 2, out);
}

}  // namespace

TEST_CASE("full height is ceil(log2(n+1))", "[kdtree]") {
  CHECK(full_height_for(0) == 0);
  CHECK(full_height_for(1) == 1);
  CHECK(full_height_for(2) == 2);
  CHECK(full_height_for(3) == 2);
  CHECK(full_height_for(4) == 3);
  CHECK(full_height_for(7) == 3);
  CHECK(full_height_for(8) == 4);
  CHECK(full_height_for(124668) == 17);
}

TEST_CASE("canonical tree: every point once, median split in (coordinate, index) order", "[kdtree]") {
  for (auto kind :
       {CloudKind::Uniform, CloudKind::Duplicates, CloudKind::AllEqual, CloudKind::Collinear, CloudKind::Grid}) {
    for (std::size_t n : {1u, 2u, 3u, 10u, 257u, 1000u}) {
      for (auto rule : {SplitRule::WidestExtent, SplitRule::RoundRobin}) {
        INFO(name(kind) << " n=" << n << " split=" << to_string(rule));
        const PointCloud c = make_cloud(kind, n, n * 31 + 7);
        const KdTree t = build_kdtree(c, -1, rule);
        REQUIRE(t.top_height == t.full_height);
        REQUIRE(t.leaf_index.empty());
        std::vector<std::uint32_t> all;
        collect(t, 0, all);
        std::sort(all.begin(), all.end());
        REQUIRE(all.size() == n);
        for (std::uint32_t i = 0; i < n; ++i) REQUIRE(all[i] == i);
        // Each node: left subtree before it, right subtree after it, sizes floor(m/2) and the rest.
        for (std::uint32_t node = 0; node < t.top.size(); ++node) {
          if (t.top[node].empty()) continue;
          const int axis = t.top[node].axis;
          if (rule == SplitRule::RoundRobin) {
            int depth = 0;
            for (std::uint32_t x = node; x > 0; x = (x - 1) / 2) ++depth;
            REQUIRE(axis == depth % 3);
          }
          std::vector<std::uint32_t> left, right;
          collect(t, 2 * node + 1, left);
          collect(t, 2 * node + 2, right);
          const std::size_t m = left.size() + right.size() + 1;
          REQUIRE(left.size() == m / 2);
          for (auto i : left) REQUIRE(before(c, i, t.top[node].index, axis));
          for (auto i : right) REQUIRE(before(c, t.top[node].index, i, axis));
          REQUIRE(t.top[node].point.x == c[t.top[node].index].x);
        }
      }
    }
  }
}

TEST_CASE("widest-extent split axis, ties to x then y then z", "[kdtree]") {
  PointCloud along_y = {{0, 0, 0}, {1, 5, 0}, {0.5f, -5, 1}};
  CHECK(build_kdtree(along_y, -1).top[0].axis == 1);
  PointCloud along_z = {{0, 0, -9}, {1, 1, 9}, {0, 0, 0}};
  CHECK(build_kdtree(along_z, -1).top[0].axis == 2);
  PointCloud tie_xy = {{0, 0, 0}, {2, 2, 1}};
  CHECK(build_kdtree(tie_xy, -1).top[0].axis == 0);
  PointCloud tie_yz = {{0, 0, 0}, {1, 2, 2}};
  CHECK(build_kdtree(tie_yz, -1).top[0].axis == 1);
  // Root of 3 points on x: median is the middle one by (x, index).
  PointCloud line = {{2, 0, 0}, {0, 0, 0}, {1, 0, 0}};
  const KdTree t = build_kdtree(line, -1);
  CHECK(t.top[0].index == 2);
  CHECK(t.top[1].index == 1);
  CHECK(t.top[2].index == 0);
}

TEST_CASE("two-stage tree: top-tree is the canonical tree's first h levels, leaf sets its subtrees", "[kdtree]") {
  const PointCloud c = make_cloud(CloudKind::Uniform, 777, 5);
  const KdTree canon = build_kdtree(c, -1);
  for (int h = 0; h <= canon.full_height; ++h) {
    INFO("h=" << h);
    const KdTree t = build_kdtree(c, h);
    REQUIRE(t.top.size() == (std::size_t{1} << h) - 1);
    REQUIRE(t.num_leaves() == (1u << h));
    for (std::size_t n = 0; n < t.top.size(); ++n) {
      REQUIRE(t.top[n].index == canon.top[n].index);
      REQUIRE(t.top[n].axis == canon.top[n].axis);
    }
    std::size_t total = 0;
    for (std::uint32_t j = 0; j < t.num_leaves(); ++j) {
      std::vector<std::uint32_t> expect;
      collect(canon, (1u << h) - 1 + j, expect);
      std::sort(expect.begin(), expect.end());
      std::vector<std::uint32_t> got(t.leaf_index.begin() + t.leaf_begin[j],
                                     t.leaf_index.begin() + t.leaf_begin[j + 1]);
      REQUIRE(got == expect);  // ascending index order
      for (std::uint32_t p = t.leaf_begin[j]; p < t.leaf_begin[j + 1]; ++p)
        REQUIRE(t.leaf_points[p].y == c[t.leaf_index[p]].y);
      total += got.size();
    }
    REQUIRE(total + (t.top.size() - static_cast<std::size_t>(std::count_if(
                                        t.top.begin(), t.top.end(), [](const TopNode& x) { return x.empty(); }))) ==
            c.size());
  }
}

TEST_CASE("bad tree inputs are rejected with clear errors", "[kdtree]") {
  const PointCloud c = make_cloud(CloudKind::Uniform, 100, 1);
  CHECK_THROWS_AS(build_kdtree(c, 8), std::invalid_argument);  // full height is 7
  CHECK_THROWS_WITH(build_kdtree(c, 8), Catch::Contains("exceeds the full height 7"));
  CHECK_THROWS_AS(build_kdtree(PointCloud{}, 0), InputError);
  PointCloud nan = c;
  nan[42].y = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_WITH(build_kdtree(nan, 3), Catch::Contains("point 42"));
  CHECK_THROWS_AS(parse_split_rule("median"), std::invalid_argument);
}
