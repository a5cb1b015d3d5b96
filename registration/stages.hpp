// Internal to the pipeline (pipeline_*.cpp): the stages, their table and the functions they run,
// one translation unit per stage group so PCL's templates compile in pieces. A new stage is its
// run function (in a stage group's file or a new one), its row in stage_table() below with a
// field of PipelineState when it hands data on, and its keys in pipeline_config.hpp
// (docs/extending.md, "A pipeline stage").
#pragma once

#include <memory>
#include <vector>

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
using Tree = TigrisKdTree<pcl::PointXYZ>;
// A plug-in tree built on `cloud`, charged to `counters`, its searches of every point in order
// announced (one job in the loop).
Tree::Ptr announced_tree(const Cloud::Ptr& cloud, const SearchSettings& s, const Counters& counters);
// PCL's statistical outlier removal with its kNN searches on `tree` (announced_tree(cloud)).
Cloud::Ptr remove_outliers(const Cloud::ConstPtr& cloud, const PipelineConfig& c, const Tree::Ptr& tree);
// Normals by radius search on `tree` (announced_tree(cloud)); points whose normal is undefined
// (too few neighbours) are dropped from `cloud` and the normals, so both stay aligned. Returns
// the dropped count.
std::size_t estimate_normals(Cloud::Ptr& cloud, Normals::Ptr& normals, const PipelineConfig& c, const Tree::Ptr& tree);
// Key points of `cloud` (the sensor at the origin, for NARF's range image).
Cloud::Ptr detect_keypoints(const Cloud::ConstPtr& cloud, const Normals::ConstPtr& normals, const PipelineConfig& c,
                            const SearchSettings& s, const Counters& counters);

// pipeline_features.cpp
struct Descriptors {
  Cloud::Ptr keypoints;  // the key points that got a finite descriptor, aligned with the features
  pcl::PointCloud<pcl::FPFHSignature33>::Ptr fpfh;
  pcl::PointCloud<pcl::SHOT352>::Ptr shot;
  std::size_t dropped = 0;  // key points without a finite descriptor
};
Descriptors describe(const Cloud::ConstPtr& keypoints, const Cloud::ConstPtr& surface, const Normals::ConstPtr& normals,
                     const PipelineConfig& c, const SearchSettings& s, const Counters& counters);
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
  std::string stop;                      // why ICP stopped (PCL's convergence state)
  std::size_t last_correspondences = 0;  // pairs the last iteration used
  std::string degenerate;                // why no transform could be estimated (transform NaN); "" when fine
};
IcpOutcome run_icp(const Cloud::ConstPtr& source, const Normals::ConstPtr& source_normals,
                   const Cloud::ConstPtr& target, const Normals::ConstPtr& target_normals, const Eigen::Matrix4d& guess,
                   const PipelineConfig& c, const SearchSettings& s, const Counters& counters);

// ---------------------------------------------------------------------------------------------
// The stages and what they hand on to each other.

struct PipelineState {
  const PipelineConfig& c;
  // The searches' settings: approximate search only where the paper approximates (normals,
  // RPCE), error injection only on normal estimation's (a shell) and RPCE's (the K-th nearest).
  SearchSettings exact, normals_search, rpce_search;
  Cloud::Ptr src, tgt;  // source = the later frame
  Normals::Ptr src_n, tgt_n;
  Cloud::Ptr src_k, tgt_k;
  Descriptors src_d, tgt_d;
  pcl::Correspondences pairs;
  RegistrationResult& r;  // the initial and final transforms, the status
};

// A stage as it runs: the counters its searches charge, and its report's stage-specific counts.
struct StageContext {
  Counters counters;
  nlohmann::json& info;
};

// One stage: its key, title and parts (pipeline.hpp), the settings of its 3D KD-tree searches
// (null: it does not search the 3D tree), whether it runs (null: always), and its work.
struct StageDef {
  StageInfo info;
  const SearchSettings* (*searches)(const PipelineState&);
  bool (*enabled)(const PipelineConfig&);
  void (*run)(PipelineState&, StageContext&);
};

void run_outlier_removal(PipelineState& s, StageContext& st);  // pipeline_front.cpp
void run_normals(PipelineState& s, StageContext& st);
void run_keypoints(PipelineState& s, StageContext& st);
void run_descriptors(PipelineState& s, StageContext& st);  // pipeline_features.cpp
void run_kpce(PipelineState& s, StageContext& st);
void run_rejection(PipelineState& s, StageContext& st);  // pipeline_icp.cpp
void run_icp_stage(PipelineState& s, StageContext& st);

// The stages in the pipeline's order (the paper's Table 1, outlier removal first).
inline const std::vector<StageDef>& stage_table() {
  static const std::vector<StageDef> table = {
      {{"outlier_removal", "outlier removal", {}},
       [](const PipelineState& s) -> const SearchSettings* { return &s.exact; },
       [](const PipelineConfig& c) { return c.outlier_removal.enabled; },
       run_outlier_removal},
      {{"normals", "normal estimation", {}},
       [](const PipelineState& s) -> const SearchSettings* { return &s.normals_search; },
       nullptr,
       run_normals},
      {{"keypoints", "key-point detection", {}},
       [](const PipelineState& s) -> const SearchSettings* {
         return s.c.keypoints.method == KeypointMethod::Harris3d ? &s.exact : nullptr;  // NARF, SIFT: no 3D tree
       },
       nullptr,
       run_keypoints},
      {{"descriptors", "descriptor calculation", {}},
       [](const PipelineState& s) -> const SearchSettings* { return &s.exact; },
       nullptr,
       run_descriptors},
      {{"kpce", "KPCE", {}}, nullptr, nullptr, run_kpce},  // feature space: PCL's FLANN, never the 3D tree
      {{"rejection", "rejection", {}}, nullptr, nullptr, run_rejection},
      // ICP is one stage here; the paper splits it into RPCE (its KD-tree searches) and
      // transformation estimation (the rest).
      {{"icp", "ICP", {{"RPCE", "kdtree_search"}, {"transformation estimation", "rest"}}},
       [](const PipelineState& s) -> const SearchSettings* { return &s.rpce_search; },
       nullptr,
       run_icp_stage},
  };
  return table;
}

}  // namespace tigris::registration::stages
