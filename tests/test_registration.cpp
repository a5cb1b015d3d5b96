// The PCL search plug-in (registration/search_plugin.hpp) through PCL's own entry points:
// normals and correspondences equal to those PCL computes with its KdTreeFLANN.
#include <catch2/catch.hpp>

#include <algorithm>

#include <pcl/features/normal_3d.h>
#include <pcl/registration/correspondence_estimation.h>

#include "registration/search_plugin.hpp"
#include "sw_ref/arith.hpp"
#include "test_util.hpp"

using namespace tigris;
using namespace tigris::registration;

namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr to_pcl(const PointCloud& c) {
  auto out = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const Point3& p : c) out->push_back({p.x, p.y, p.z});
  return out;
}

template <class T>
typename TigrisKdTree<T>::Ptr plugin(Backend b, std::shared_ptr<SearchCounters> counters, float nn_thd = 1.2f) {
  SearchSettings s;
  s.backend = b;
  s.top_height = 5;
  s.nn_thd = nn_thd;
  return std::make_shared<TigrisKdTree<T>>(s, counters);
}

}  // namespace

TEST_CASE("plug-in: NormalEstimation gives the normals KdTreeFLANN gives", "[registration]") {
  const auto cloud = to_pcl(test::make_cloud(test::CloudKind::Uniform, 3000, 41));
  const auto normals = [&](pcl::search::KdTree<pcl::PointXYZ>::Ptr tree) {
    pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
    ne.setInputCloud(cloud);
    ne.setSearchMethod(tree);
    ne.setRadiusSearch(1.5);
    pcl::PointCloud<pcl::Normal> out;
    ne.compute(out);
    return out;
  };
  auto counters = std::make_shared<SearchCounters>();
  const auto flann = normals(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  const auto exact = normals(plugin<pcl::PointXYZ>(Backend::Exact, counters));
  REQUIRE(flann.size() == exact.size());
  std::size_t compared = 0;
  for (std::size_t i = 0; i < flann.size(); ++i) {
    if (!std::isfinite(flann[i].normal_x)) {
      CHECK_FALSE(std::isfinite(exact[i].normal_x));
      continue;
    }
    // The same neighbour sets (in another order: the covariance sums round differently).
    CHECK(std::abs(std::abs(flann[i].normal_x * exact[i].normal_x + flann[i].normal_y * exact[i].normal_y +
                            flann[i].normal_z * exact[i].normal_z) -
                   1.0f) < 1e-4f);
    CHECK(exact[i].curvature == Approx(flann[i].curvature).margin(1e-4));
    ++compared;
  }
  CHECK(compared > 2900);
  CHECK(counters->searches == cloud->size());
  CHECK(counters->builds == 1);
  CHECK(counters->visits.leaf_points > 0);
}

TEST_CASE("plug-in: CorrespondenceEstimation pairs equal KdTreeFLANN's, reciprocal too", "[registration]") {
  const auto target = to_pcl(test::make_cloud(test::CloudKind::Uniform, 2000, 42));
  // Random points with no equidistant neighbours, so FLANN's tie-breaking never matters.
  const auto source = to_pcl(test::make_cloud(test::CloudKind::Uniform, 800, 99));
  const auto pairs = [&](pcl::search::KdTree<pcl::PointXYZ>::Ptr t, pcl::search::KdTree<pcl::PointXYZ>::Ptr s,
                         bool reciprocal) {
    pcl::registration::CorrespondenceEstimation<pcl::PointXYZ, pcl::PointXYZ> ce;
    ce.setInputSource(source);
    ce.setInputTarget(target);
    ce.setSearchMethodTarget(t);
    ce.setSearchMethodSource(s);
    pcl::Correspondences c;
    if (reciprocal)
      ce.determineReciprocalCorrespondences(c);
    else
      ce.determineCorrespondences(c);
    return c;
  };
  for (bool reciprocal : {false, true}) {
    auto counters = std::make_shared<SearchCounters>();
    const auto f = pairs(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>(),
                         std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>(), reciprocal);
    const auto g = pairs(plugin<pcl::PointXYZ>(Backend::Exact, counters),
                         plugin<pcl::PointXYZ>(Backend::Exact, counters), reciprocal);
    REQUIRE(f.size() == g.size());
    CHECK(f.size() > (reciprocal ? 100u : 799u));
    for (std::size_t i = 0; i < f.size(); ++i) {
      REQUIRE(f[i].index_query == g[i].index_query);
      CHECK(f[i].index_match == g[i].index_match);
      CHECK(f[i].distance == g[i].distance);
    }
    CHECK(counters->searches >= source->size());
  }
}

TEST_CASE("plug-in: approximate search with thd 0 equals exact, a large thd makes followers", "[registration]") {
  const auto cloud = to_pcl(test::make_cloud(test::CloudKind::Uniform, 2000, 43));
  const auto queries = to_pcl(test::make_queries(test::make_cloud(test::CloudKind::Uniform, 2000, 43), 400, 43));
  auto ce = std::make_shared<SearchCounters>(), ca0 = std::make_shared<SearchCounters>(),
       ca = std::make_shared<SearchCounters>();
  auto exact = plugin<pcl::PointXYZ>(Backend::Exact, ce);
  auto approx0 = plugin<pcl::PointXYZ>(Backend::Approx, ca0, 0.0f);
  auto approx = plugin<pcl::PointXYZ>(Backend::Approx, ca, 1.2f);
  for (auto t : {exact, approx0, approx}) t->setInputCloud(cloud);
  pcl::Indices ie, ia;
  std::vector<float> de, da;
  for (const auto& q : *queries) {
    exact->nearestKSearch(q, 3, ie, de);
    approx0->nearestKSearch(q, 3, ia, da);
    CHECK(ie == ia);
    CHECK(de == da);
    approx->nearestKSearch(q, 3, ia, da);
  }
  CHECK(ca0->leaders.followers == 0);
  CHECK(ca->leaders.followers > 0);
  CHECK(ca->visits.leaf_points < ce->visits.leaf_points);
  CHECK_THROWS_WITH(parse_backend("kd"), Catch::Contains("flann, exact or approx"));
}

namespace {

// The brute-force neighbour list of q in canonical (dist2, index) order.
std::vector<Neighbor> sorted_neighbors(const pcl::PointCloud<pcl::PointXYZ>& cloud, const pcl::PointXYZ& q) {
  std::vector<Neighbor> all;
  for (std::size_t i = 0; i < cloud.size(); ++i)
    all.push_back({static_cast<std::uint32_t>(i), dist2({q.x, q.y, q.z}, {cloud[i].x, cloud[i].y, cloud[i].z})});
  std::sort(all.begin(), all.end(), Closer());
  return all;
}

template <class T>
typename TigrisKdTree<T>::Ptr injected(Backend b, int kth, float inner = 0.0f, float outer = 0.0f, int height = 5) {
  SearchSettings s;
  s.backend = b;
  s.top_height = height;
  s.inject_kth = kth;
  s.shell_inner = inner;
  s.shell_outer = outer;
  return std::make_shared<TigrisKdTree<T>>(s, std::make_shared<SearchCounters>());
}

}  // namespace

TEST_CASE("leaf size: the lowest top height whose leaf sets hold at most that many points", "[registration]") {
  SearchSettings s;
  s.top_height = 7;
  CHECK(s.height_for(1000) == 7);  // no leaf size: the top height
  s.leaf_size = 32;
  CHECK(s.height_for(32) == 0);
  CHECK(s.height_for(33) == 1);
  CHECK(s.height_for(64) == 1);
  CHECK(s.height_for(65) == 1);  // the root keeps one point: 32 + 32
  CHECK(s.height_for(66) == 2);
  for (std::size_t n : {100u, 1000u, 4097u, 20000u}) {
    PointCloud cloud(n);
    for (std::size_t i = 0; i < n; ++i)
      cloud[i] = {static_cast<float>(i % 37), static_cast<float>(i % 101) * 0.5f, static_cast<float>(i) * 0.01f};
    const int h = s.height_for(n);
    for (int height : {h - 1, h}) {
      if (height < 0) continue;
      const KdTree t = build_kdtree(cloud, height);
      std::uint32_t largest = 0;
      for (std::uint32_t j = 0; j < t.num_leaves(); ++j) largest = std::max(largest, t.leaf_size(j));
      INFO("n " << n << " height " << height);
      CHECK((largest <= 32) == (height == h));  // h gets there, one level less does not
    }
  }
}

TEST_CASE("plug-in error injection: an NN search returns exactly the K-th nearest neighbour", "[registration]") {
  for (const auto kind : {test::CloudKind::Uniform, test::CloudKind::Duplicates}) {
    const auto cloud = to_pcl(test::make_cloud(kind, 1500, 44));
    const auto queries = to_pcl(test::make_queries(test::make_cloud(kind, 1500, 44), 120, 44));
    for (const int kth : {1, 2, 4, 17, 32}) {
      for (const int height : {0, 4, 30}) {
        auto tree = injected<pcl::PointXYZ>(Backend::Exact, kth, 0.0f, 0.0f, height);
        tree->setInputCloud(cloud);
        pcl::Indices idx;
        std::vector<float> d2;
        for (const auto& q : *queries) {
          const std::vector<Neighbor> truth = sorted_neighbors(*cloud, q);
          INFO(test::name(kind) << " K " << kth << " height " << height);
          REQUIRE(tree->nearestKSearch(q, 1, idx, d2) == 1);
          CHECK(idx[0] == static_cast<pcl::index_t>(truth[static_cast<std::size_t>(kth - 1)].index));
          CHECK(d2[0] == truth[static_cast<std::size_t>(kth - 1)].dist2);
          // k > 1: ranks K .. K+k-1.
          REQUIRE(tree->nearestKSearch(q, 3, idx, d2) == 3);
          for (std::size_t j = 0; j < 3; ++j)
            CHECK(idx[j] == static_cast<pcl::index_t>(truth[static_cast<std::size_t>(kth - 1) + j].index));
        }
      }
    }
  }
  // FLANN (uniform points: no equidistant neighbours, so its tie order never matters).
  const auto cloud = to_pcl(test::make_cloud(test::CloudKind::Uniform, 1500, 45));
  auto tree = injected<pcl::PointXYZ>(Backend::Flann, 8);
  tree->setInputCloud(cloud);
  pcl::Indices idx;
  std::vector<float> d2;
  for (std::size_t i = 0; i < 200; i += 7) {
    const auto& q = (*cloud)[i];
    REQUIRE(tree->nearestKSearch(q, 1, idx, d2) == 1);
    CHECK(idx[0] == static_cast<pcl::index_t>(sorted_neighbors(*cloud, q)[7].index));
  }
  // Fewer than K points: the farthest (an NN search never comes back empty).
  const auto three = to_pcl(PointCloud{{0, 0, 0}, {1, 0, 0}, {3, 0, 0}});
  auto small = injected<pcl::PointXYZ>(Backend::Exact, 8);
  small->setInputCloud(three);
  REQUIRE(small->nearestKSearch(pcl::PointXYZ(0.1f, 0, 0), 1, idx, d2) == 1);
  CHECK(idx[0] == 2);
}

TEST_CASE("plug-in error injection: a radius search returns exactly the shell R1 <= d <= R2", "[registration]") {
  const float r1 = 0.6f, r2 = 1.7f;
  for (const auto kind : {test::CloudKind::Uniform, test::CloudKind::Grid}) {
    const auto cloud = to_pcl(test::make_cloud(kind, 2000, 46));
    const auto queries = to_pcl(test::make_queries(test::make_cloud(kind, 2000, 46), 150, 46));
    for (const Backend b : {Backend::Exact, Backend::Flann}) {
      auto tree = injected<pcl::PointXYZ>(b, 1, r1, r2);
      tree->setInputCloud(cloud);
      pcl::Indices idx;
      std::vector<float> d2;
      std::size_t nonempty = 0;
      for (const auto& q : *queries) {
        std::vector<Neighbor> shell;
        for (const Neighbor& n : sorted_neighbors(*cloud, q))
          if (n.dist2 >= square(r1) && n.dist2 <= square(r2)) shell.push_back(n);
        INFO(test::name(kind) << " " << to_string(b));
        // The requested radius (1.0) is replaced by the shell.
        const int n = tree->radiusSearch(q, 1.0, idx, d2);
        REQUIRE(n == static_cast<int>(shell.size()));
        nonempty += n > 0;
        if (b == Backend::Exact) {  // canonical order, bit-exact distances
          for (std::size_t j = 0; j < shell.size(); ++j) {
            CHECK(idx[j] == static_cast<pcl::index_t>(shell[j].index));
            CHECK(d2[j] == shell[j].dist2);
          }
        } else {  // FLANN's tie order is its own: compare as sets
          std::vector<pcl::index_t> want;
          for (const Neighbor& s : shell) want.push_back(static_cast<pcl::index_t>(s.index));
          std::sort(want.begin(), want.end());
          std::sort(idx.begin(), idx.end());
          CHECK(idx == want);
        }
        // max_nn keeps the first max_nn shell points.
        if (b == Backend::Exact && shell.size() > 4) {
          REQUIRE(tree->radiusSearch(q, 1.0, idx, d2, 4) == 4);
          CHECK(idx[3] == static_cast<pcl::index_t>(shell[3].index));
        }
      }
      CHECK(nonempty > 100);
    }
  }
}

TEST_CASE("plug-in error injection: K = 1 and no shell search as without injection and bad values are rejected",
          "[registration]") {
  const auto cloud = to_pcl(test::make_cloud(test::CloudKind::Uniform, 1000, 47));
  auto plain = plugin<pcl::PointXYZ>(Backend::Exact, std::make_shared<SearchCounters>());
  auto k1 = injected<pcl::PointXYZ>(Backend::Exact, 1);
  plain->setInputCloud(cloud);
  k1->setInputCloud(cloud);
  pcl::Indices a, b;
  std::vector<float> da, db;
  for (std::size_t i = 0; i < cloud->size(); i += 13) {
    plain->nearestKSearch((*cloud)[i], 2, a, da);
    k1->nearestKSearch((*cloud)[i], 2, b, db);
    CHECK(a == b);
    plain->radiusSearch((*cloud)[i], 1.2, a, da);
    k1->radiusSearch((*cloud)[i], 1.2, b, db);
    CHECK(a == b);
    CHECK(da == db);
  }
  const auto bad = [](int kth, float inner, float outer) {
    injected<pcl::PointXYZ>(Backend::Exact, kth, inner, outer);
  };
  CHECK_THROWS_WITH(bad(0, 0, 0), Catch::Contains("inject_kth must be >= 1"));
  CHECK_THROWS_WITH(bad(1, 0.5f, 0.5f), Catch::Contains("0 <= shell_inner < shell_outer"));
  CHECK_THROWS_WITH(bad(1, -0.1f, 0.5f), Catch::Contains("0 <= shell_inner < shell_outer"));
  CHECK_NOTHROW(bad(1, 0.0f, 0.5f));
}
