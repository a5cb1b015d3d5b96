// Internal to the pipeline (pipeline_*.cpp): the stage functions, one translation unit per
// stage group so PCL's templates compile in pieces.
#pragma once

#include <memory>

#include <pcl/correspondence.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "pipeline.hpp"

namespace tigris::registration::stages {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Normals = pcl::PointCloud<pcl::Normal>;
using Counters = std::shared_ptr<SearchCounters>;

// A fresh plug-in tree charged to `counters`.
template <class PointT>
typename TigrisKdTree<PointT>::Ptr make_tree(const SearchSettings& s, const Counters& counters) {
  return std::make_shared<TigrisKdTree<PointT>>(s, counters);
}

// pipeline_front.cpp
Cloud::Ptr remove_outliers(const Cloud::ConstPtr& cloud, const PipelineConfig& c, const SearchSettings& s,
                           const Counters& counters);
// Normals by radius search; points whose normal is undefined (too few neighbours) are dropped
// from `cloud` and the normals, so both stay aligned. Returns the dropped count.
std::size_t estimate_normals(Cloud::Ptr& cloud, Normals::Ptr& normals, const PipelineConfig& c,
                             const SearchSettings& s, const Counters& counters);
// Key points of `cloud` (the sensor at the origin, for NARF's range image).
Cloud::Ptr detect_keypoints(const Cloud::ConstPtr& cloud, const Normals::ConstPtr& normals,
                            const PipelineConfig& c, const SearchSettings& s, const Counters& counters);

// pipeline_features.cpp
struct Descriptors {
  Cloud::Ptr keypoints;  // the key points that got a finite descriptor, aligned with the features
  pcl::PointCloud<pcl::FPFHSignature33>::Ptr fpfh;
  pcl::PointCloud<pcl::SHOT352>::Ptr shot;
  std::size_t dropped = 0;  // key points without a finite descriptor
};
Descriptors describe(const Cloud::ConstPtr& keypoints, const Cloud::ConstPtr& surface,
                     const Normals::ConstPtr& normals, const PipelineConfig& c, const SearchSettings& s,
                     const Counters& counters);
// Feature-space nearest neighbours source -> target (exact, PCL's FLANN KD-tree on features).
pcl::Correspondences match_features(const Descriptors& source, const Descriptors& target, bool reciprocal);

// pipeline_icp.cpp
struct Rejection {
  pcl::Correspondences inliers;
  Eigen::Matrix4d initial = Eigen::Matrix4d::Identity();
  bool fallback = false;  // too few inliers: ICP starts from the identity
};
Rejection reject(const Descriptors& source, const Descriptors& target, const pcl::Correspondences& all,
                 const PipelineConfig& c);
struct IcpOutcome {
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();
  int iterations = 0;
  bool converged = false;
  std::string stop;      // why ICP stopped (PCL's convergence state)
  std::size_t last_correspondences = 0;  // pairs the last iteration used
  std::string degenerate;  // why no transform could be estimated (transform NaN); "" when fine
};
IcpOutcome run_icp(const Cloud::ConstPtr& source, const Normals::ConstPtr& source_normals,
                   const Cloud::ConstPtr& target, const Normals::ConstPtr& target_normals,
                   const Eigen::Matrix4d& guess, const PipelineConfig& c, const SearchSettings& s,
                   const Counters& counters);

}  // namespace tigris::registration::stages
