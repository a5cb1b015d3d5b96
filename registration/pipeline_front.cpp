// Pipeline front: statistical outlier removal, normal estimation, key points.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <pcl/common/angles.h>
#include <pcl/features/normal_3d.h>
#include <pcl/features/range_image_border_extractor.h>
#include <pcl/keypoints/harris_3d.h>
#include <pcl/keypoints/narf_keypoint.h>
#include <pcl/range_image/range_image.h>

// SIFT on an x, y, z cloud: the z coordinate stands in for intensity (PCL 1.13 has no field
// selector for PointXYZ; this is the one PCL's SIFT tutorial defines).
#include <pcl/keypoints/sift_keypoint.h>
namespace pcl {
template <>
struct SIFTKeypointFieldSelector<PointXYZ> {
  inline float operator()(const PointXYZ& p) const { return p.z; }
};
}  // namespace pcl

#include "stages.hpp"

namespace tigris::registration::stages {
Tree::Ptr announced_tree(const Cloud::Ptr& cloud, const SearchSettings& s, const Counters& counters) {
  auto tree = make_tree<pcl::PointXYZ>(s, counters);
  tree->setInputCloud(cloud);
  tree->expect_queries(*cloud);  // in the loop: every point, in order, is one job
  return tree;
}

// PCL's StatisticalOutlierRemoval keeps its search object private (it makes its own FLANN
// tree), so this is its algorithm (PCL 1.13, filters/impl/statistical_outlier_removal.hpp) with
// the kNN searches on the plug-in: a point's score is the mean distance to its mean_k nearest
// other points; points scoring above mean + stddev_mul * sigma of all scores are removed.
Cloud::Ptr remove_outliers(const Cloud::ConstPtr& cloud, const PipelineConfig& c, const Tree::Ptr& tree) {
  const int k = c.outlier_removal.mean_k + 1;  // the query point itself comes first
  pcl::Indices nn(static_cast<std::size_t>(k));
  std::vector<float> d2(static_cast<std::size_t>(k));
  std::vector<double> score(cloud->size(), 0.0);
  double sum = 0.0, sq_sum = 0.0;
  std::size_t valid = 0;
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    const int n = tree->nearestKSearch((*cloud)[i], k, nn, d2);
    if (n == 0) continue;  // kept, not scored (as PCL)
    double dist_sum = 0.0;
    for (int j = 1; j < n; ++j) dist_sum += std::sqrt(static_cast<double>(d2[static_cast<std::size_t>(j)]));
    score[i] = dist_sum / c.outlier_removal.mean_k;
    sum += score[i];
    sq_sum += score[i] * score[i];
    ++valid;
  }
  auto out = std::make_shared<Cloud>();
  if (valid < 2) {
    *out = *cloud;
    return out;
  }
  const double mean = sum / static_cast<double>(valid);
  const double variance = (sq_sum - sum * sum / static_cast<double>(valid)) / static_cast<double>(valid - 1);
  const double threshold = mean + c.outlier_removal.stddev_mul * std::sqrt(std::max(variance, 0.0));
  for (std::size_t i = 0; i < cloud->size(); ++i)
    if (score[i] <= threshold) out->push_back((*cloud)[i]);
  return out;
}

std::size_t estimate_normals(Cloud::Ptr& cloud, Normals::Ptr& normals, const PipelineConfig& c, const Tree::Ptr& tree) {
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;  // never NormalEstimationOMP
  ne.setInputCloud(cloud);
  ne.setSearchMethod(tree);  // built on `cloud` already: PCL searches every point in order (one job)
  ne.setRadiusSearch(c.normals.radius);
  ne.setViewPoint(0.0f, 0.0f, 0.0f);  // the sensor: normals face it
  Normals all;
  ne.compute(all);
  auto kept_cloud = std::make_shared<Cloud>();
  normals = std::make_shared<Normals>();
  for (std::size_t i = 0; i < all.size(); ++i) {
    const pcl::Normal& n = all[i];
    if (!std::isfinite(n.normal_x) || !std::isfinite(n.normal_y) || !std::isfinite(n.normal_z) ||
        !std::isfinite(n.curvature))
      continue;
    kept_cloud->push_back((*cloud)[i]);
    normals->push_back(n);
  }
  const std::size_t dropped = cloud->size() - kept_cloud->size();
  cloud = kept_cloud;
  return dropped;
}

namespace {

Cloud::Ptr narf(const Cloud::ConstPtr& cloud, const PipelineConfig& c) {
  // A spherical range image around the sensor (at the origin, Velodyne axes: LASER_FRAME).
  pcl::RangeImage image;
  image.createFromPointCloud(*cloud, pcl::deg2rad(static_cast<float>(c.keypoints.narf.angular_resolution_deg)),
                             pcl::deg2rad(360.0f), pcl::deg2rad(180.0f), Eigen::Affine3f::Identity(),
                             pcl::RangeImage::LASER_FRAME, 0.0f, 0.0f, 1);
  pcl::RangeImageBorderExtractor borders;
  pcl::NarfKeypoint detector(&borders);
  detector.setRangeImage(&image);
  detector.getParameters().support_size = static_cast<float>(c.keypoints.narf.support_size);
  pcl::PointCloud<int> indices;
  detector.compute(indices);
  auto out = std::make_shared<Cloud>();
  for (int i : indices) {
    const auto& p = image[static_cast<std::size_t>(i)];
    out->push_back(pcl::PointXYZ(p.x, p.y, p.z));
  }
  return out;
}

Cloud::Ptr harris(const Cloud::ConstPtr& cloud, const Normals::ConstPtr& normals, const PipelineConfig& c,
                  const SearchSettings& s, const Counters& counters) {
  pcl::HarrisKeypoint3D<pcl::PointXYZ, pcl::PointXYZI, pcl::Normal> detector;
  detector.setNumberOfThreads(1);  // its OpenMP loops would search the plug-in concurrently
  detector.setInputCloud(cloud);
  detector.setNormals(normals);  // after the input: setInputCloud drops normals of another cloud
  const auto tree = make_tree<pcl::PointXYZ>(s, counters);
  tree->expect_queries(*cloud);  // in the loop: the response pass is one job; refinement falls back
  detector.setSearchMethod(tree);
  detector.setRadius(static_cast<float>(c.keypoints.harris3d.radius));
  detector.setThreshold(static_cast<float>(c.keypoints.harris3d.threshold));
  detector.setNonMaxSupression(c.keypoints.harris3d.non_max_suppression);
  detector.setRefine(c.keypoints.harris3d.refine);
  pcl::PointCloud<pcl::PointXYZI> found;
  detector.compute(found);
  auto out = std::make_shared<Cloud>();
  for (const auto& p : found)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) out->push_back(pcl::PointXYZ(p.x, p.y, p.z));
  return out;
}

Cloud::Ptr sift(const Cloud::ConstPtr& cloud, const PipelineConfig& c) {
  // PCL's SIFT builds its own FLANN trees per octave (it ignores a search object): these
  // searches are not counted.
  pcl::SIFTKeypoint<pcl::PointXYZ, pcl::PointWithScale> detector;
  detector.setInputCloud(cloud);
  detector.setScales(static_cast<float>(c.keypoints.sift.min_scale), c.keypoints.sift.octaves,
                     c.keypoints.sift.scales_per_octave);
  detector.setMinimumContrast(static_cast<float>(c.keypoints.sift.min_contrast));
  pcl::PointCloud<pcl::PointWithScale> found;
  detector.compute(found);
  auto out = std::make_shared<Cloud>();
  for (const auto& p : found) out->push_back(pcl::PointXYZ(p.x, p.y, p.z));
  return out;
}

}  // namespace

Cloud::Ptr detect_keypoints(const Cloud::ConstPtr& cloud, const Normals::ConstPtr& normals, const PipelineConfig& c,
                            const SearchSettings& s, const Counters& counters) {
  switch (c.keypoints.method) {
    case KeypointMethod::Narf: return narf(cloud, c);
    case KeypointMethod::Harris3d: return harris(cloud, normals, c, s, counters);
    default: return sift(cloud, c);
  }
}

// ---------------------------------------------------------------------------------------------
// The stages of this group (stage_table() in stages.hpp).

// Both clouds' trees are built and their searches announced first, so that in the loop the
// target's job runs beside the source's (the trees built in the same order as searched).
void run_outlier_removal(PipelineState& s, StageContext& st) {
  const std::size_t ns = s.src->size(), nt = s.tgt->size();
  const Tree::Ptr src_tree = announced_tree(s.src, s.exact, st.counters);
  const Tree::Ptr tgt_tree = announced_tree(s.tgt, s.exact, st.counters);
  tgt_tree->prefetch_knn(s.c.outlier_removal.mean_k + 1);
  s.src = remove_outliers(s.src, s.c, src_tree);
  s.tgt = remove_outliers(s.tgt, s.c, tgt_tree);
  st.info = {
      {"source_points", ns}, {"source_kept", s.src->size()}, {"target_points", nt}, {"target_kept", s.tgt->size()}};
}

void run_normals(PipelineState& s, StageContext& st) {
  const Tree::Ptr src_tree = announced_tree(s.src, s.normals_search, st.counters);
  const Tree::Ptr tgt_tree = announced_tree(s.tgt, s.normals_search, st.counters);
  tgt_tree->prefetch_radius(s.c.normals.radius);  // PCL's radius searches ask no max_nn
  const std::size_t ds = estimate_normals(s.src, s.src_n, s.c, src_tree);
  const std::size_t dt = estimate_normals(s.tgt, s.tgt_n, s.c, tgt_tree);
  st.info = {{"source_without_normal", ds},
             {"target_without_normal", dt},
             {"source_points", s.src->size()},
             {"target_points", s.tgt->size()}};
  if (s.normals_search.injects_shell())
    st.info["injected"] = {{"error", "shell"},
                           {"inner_m", s.c.inject.normals_shell_inner},
                           {"outer_m", s.c.inject.normals_shell_outer},
                           {"instead_of_radius_m", s.c.normals.radius}};
  if (s.src->size() < 3 || s.tgt->size() < 3)
    throw std::runtime_error("registration: fewer than 3 points with a normal are left (source " +
                             std::to_string(s.src->size()) + ", target " + std::to_string(s.tgt->size()) +
                             "); is normals.radius too small for these clouds?");
}

void run_keypoints(PipelineState& s, StageContext& st) {
  s.src_k = detect_keypoints(s.src, s.src_n, s.c, s.exact, st.counters);
  s.tgt_k = detect_keypoints(s.tgt, s.tgt_n, s.c, s.exact, st.counters);
  st.info = {{"method", to_string(s.c.keypoints.method)}, {"source", s.src_k->size()}, {"target", s.tgt_k->size()}};
  if (s.c.keypoints.method == KeypointMethod::Sift)
    st.info["note"] = "PCL's SIFT searches its own FLANN trees (not counted)";
}

}  // namespace tigris::registration::stages
