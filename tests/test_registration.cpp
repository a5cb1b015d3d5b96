// The PCL search plug-in (sw_ref/registration/search_plugin.hpp) through PCL's own entry points:
// normals and correspondences equal to those PCL computes with its KdTreeFLANN.
#include <catch2/catch.hpp>

#include <pcl/features/normal_3d.h>
#include <pcl/registration/correspondence_estimation.h>

#include "sw_ref/registration/search_plugin.hpp"
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
                            flann[i].normal_z * exact[i].normal_z) - 1.0f) < 1e-4f);
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
    const auto g = pairs(plugin<pcl::PointXYZ>(Backend::Exact, counters), plugin<pcl::PointXYZ>(Backend::Exact, counters),
                         reciprocal);
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
