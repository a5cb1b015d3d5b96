// Pipeline back end: key-point correspondence rejection (the initial estimate) and ICP.
#include <cmath>
#include <functional>
#include <stdexcept>

#include <pcl/registration/correspondence_rejection_distance.h>
#include <pcl/registration/correspondence_rejection_sample_consensus.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/transformation_estimation_lm.h>
#include <pcl/registration/transformation_estimation_point_to_plane.h>
#include <pcl/registration/transformation_estimation_point_to_plane_lls.h>
#include <pcl/registration/transformation_estimation_svd.h>

#include "stages.hpp"

namespace tigris::registration::stages {
namespace {

using PN = pcl::PointNormal;
using PNCloud = pcl::PointCloud<PN>;

PNCloud::Ptr with_normals(const Cloud& cloud, const Normals& normals) {
  if (cloud.size() != normals.size()) throw std::logic_error("ICP: points and normals differ in count");
  auto out = std::make_shared<PNCloud>();
  out->resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    PN& p = (*out)[i];
    p.x = cloud[i].x;
    p.y = cloud[i].y;
    p.z = cloud[i].z;
    p.normal_x = normals[i].normal_x;
    p.normal_y = normals[i].normal_y;
    p.normal_z = normals[i].normal_z;
    p.curvature = normals[i].curvature;
  }
  return out;
}

// ICP with its iteration count and stop reason readable.
class Icp : public pcl::IterativeClosestPoint<PN, PN> {
 public:
  int iterations() const { return nr_iterations_; }
  std::size_t last_correspondences() const { return correspondences_ ? correspondences_->size() : 0; }
};

const char* stop_reason(pcl::registration::DefaultConvergenceCriteria<float>::ConvergenceState s) {
  using C = pcl::registration::DefaultConvergenceCriteria<float>;
  switch (s) {
    case C::CONVERGENCE_CRITERIA_NOT_CONVERGED: return "not_converged";
    case C::CONVERGENCE_CRITERIA_ITERATIONS: return "max_iterations";
    case C::CONVERGENCE_CRITERIA_TRANSFORM: return "transformation_epsilon";
    case C::CONVERGENCE_CRITERIA_ABS_MSE: return "absolute_mse";
    case C::CONVERGENCE_CRITERIA_REL_MSE: return "euclidean_fitness_epsilon";
    case C::CONVERGENCE_CRITERIA_NO_CORRESPONDENCES: return "too_few_correspondences";
    case C::CONVERGENCE_CRITERIA_FAILURE_AFTER_MAX_ITERATIONS: return "failure_after_max_iterations";
  }
  return "unknown";
}

// A transformation estimate that does not constrain all six degrees of freedom (a flat or
// linear cloud: point-to-plane's normal equations are singular) comes out NaN or enormous.
// PCL would apply it to the source cloud and search NaN points (FLANN asserts); this wrapper
// stops ICP at the first such estimate instead.
class Degenerate : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class GuardedEstimation : public pcl::registration::TransformationEstimation<PN, PN> {
 public:
  explicit GuardedEstimation(Ptr inner) : inner_(std::move(inner)) {}
  void estimateRigidTransformation(const PNCloud& s, const PNCloud& t, Matrix4& m) const override {
    inner_->estimateRigidTransformation(s, t, m);
    check(m);
  }
  void estimateRigidTransformation(const PNCloud& s, const pcl::Indices& is, const PNCloud& t,
                                   Matrix4& m) const override {
    inner_->estimateRigidTransformation(s, is, t, m);
    check(m);
  }
  void estimateRigidTransformation(const PNCloud& s, const pcl::Indices& is, const PNCloud& t, const pcl::Indices& it,
                                   Matrix4& m) const override {
    inner_->estimateRigidTransformation(s, is, t, it, m);
    check(m);
  }
  void estimateRigidTransformation(const PNCloud& s, const PNCloud& t, const pcl::Correspondences& c,
                                   Matrix4& m) const override {
    inner_->estimateRigidTransformation(s, t, c, m);
    check(m);
  }

 private:
  static void check(const Matrix4& m) {
    if (!m.allFinite() || m.topRightCorner<3, 1>().cwiseAbs().maxCoeff() > 1e6f)
      throw Degenerate(
          "the correspondences do not determine a rigid transform (the estimate is not finite): "
          "the clouds do not constrain all six degrees of freedom, e.g. a flat or linear scene");
  }
  Ptr inner_;
};

// RPCE with its searches batched for the accelerator in the loop. PCL's reciprocal
// estimation interleaves the two directions (a source point's search in the target tree, then
// its match's search in the source tree); here every forward search comes first, then the
// reciprocal searches of the matches within the distance, so each direction of an iteration is
// one job whose queries are known before its first search. Each tree sees the same searches in
// the same order as in PCL's loop, so the correspondences are PCL's, bit for bit, on every
// back-end (approximate search included: leader state is per tree).
class BatchedCorrespondences : public pcl::registration::CorrespondenceEstimation<PN, PN, float> {
  using Base = pcl::registration::CorrespondenceEstimation<PN, PN, float>;
  using Plugin = TigrisKdTree<PN>;

 public:
  void determineCorrespondences(pcl::Correspondences& out, double max_distance) override {
    if (initCompute())
      if (auto* t = dynamic_cast<Plugin*>(tree_.get())) t->expect_queries(*input_, indices_.get());
    Base::determineCorrespondences(out, max_distance);
  }

  void determineReciprocalCorrespondences(pcl::Correspondences& out, double max_distance) override {
    if (!initCompute() || !initComputeReciprocal()) return;
    const double max_dist_sqr = max_distance * max_distance;
    auto* forward = dynamic_cast<Plugin*>(tree_.get());
    auto* backward = dynamic_cast<Plugin*>(tree_reciprocal_.get());
    if (forward) forward->expect_queries(*input_, indices_.get());
    pcl::Indices index(1), index_back(1);
    std::vector<float> distance(1), distance_back(1);
    // Forward: each source point's nearest target point within the distance.
    std::vector<pcl::Correspondence> candidates;
    candidates.reserve(indices_->size());
    for (const auto& idx : *indices_) {
      if (tree_->nearestKSearch((*input_)[idx], 1, index, distance) < 1 || distance[0] > max_dist_sqr) continue;
      candidates.emplace_back(idx, index[0], distance[0]);
    }
    // Backward: each match's nearest source point must be the one it was matched from.
    if (backward) {
      pcl::Indices matched;
      matched.reserve(candidates.size());
      for (const auto& c : candidates) matched.push_back(c.index_match);
      backward->expect_queries(*target_, &matched);
    }
    out.clear();
    out.reserve(candidates.size());
    for (const auto& c : candidates) {
      if (tree_reciprocal_->nearestKSearch((*target_)[static_cast<std::size_t>(c.index_match)], 1, index_back,
                                           distance_back) < 1 ||
          distance_back[0] > max_dist_sqr || c.index_query != index_back[0])
        continue;
      out.push_back(c);
    }
    deinitCompute();
  }

  pcl::registration::CorrespondenceEstimationBase<PN, PN, float>::Ptr clone() const override {
    return std::make_shared<BatchedCorrespondences>(*this);
  }
};

}  // namespace

Rejection reject(const Descriptors& source, const Descriptors& target, const pcl::Correspondences& all,
                 const PipelineConfig& c) {
  Rejection r;
  if (all.size() < 3) {
    r.fallback = true;
    return r;
  }
  const auto all_ptr = std::make_shared<pcl::Correspondences>(all);
  if (c.rejection.method == RejectionMethod::Ransac) {
    pcl::registration::CorrespondenceRejectorSampleConsensus<pcl::PointXYZ> sac;
    sac.setInputSource(source.keypoints);
    sac.setInputTarget(target.keypoints);
    sac.setInlierThreshold(c.rejection.ransac_threshold);
    sac.setMaximumIterations(c.rejection.ransac_iterations);
    sac.setRefineModel(false);
    sac.getRemainingCorrespondences(all, r.inliers);
    if (r.inliers.size() >= 3) r.initial = sac.getBestTransformation().cast<double>();
  } else {
    pcl::registration::CorrespondenceRejectorDistance rej;
    rej.setInputSource<pcl::PointXYZ>(source.keypoints);
    rej.setInputTarget<pcl::PointXYZ>(target.keypoints);
    rej.setMaximumDistance(static_cast<float>(c.rejection.distance_max));
    rej.getRemainingCorrespondences(all, r.inliers);
    if (r.inliers.size() >= 3) {
      pcl::registration::TransformationEstimationSVD<pcl::PointXYZ, pcl::PointXYZ> svd;
      Eigen::Matrix4f t;
      svd.estimateRigidTransformation(*source.keypoints, *target.keypoints, r.inliers, t);
      r.initial = t.cast<double>();
    }
  }
  if (r.inliers.size() < 3 || !r.initial.allFinite()) {
    r.fallback = true;
    r.initial = Eigen::Matrix4d::Identity();
  }
  return r;
}

IcpOutcome run_icp(const Cloud::ConstPtr& source, const Normals::ConstPtr& source_normals,
                   const Cloud::ConstPtr& target, const Normals::ConstPtr& target_normals, const Eigen::Matrix4d& guess,
                   const PipelineConfig& c, const SearchSettings& s, const Counters& counters) {
  Icp icp;
  icp.setInputSource(with_normals(*source, *source_normals));
  icp.setInputTarget(with_normals(*target, *target_normals));
  // initCompute hands these trees to the correspondence estimator (it would overwrite trees set
  // on the estimator itself); the source tree serves the reciprocal direction.
  icp.setSearchMethodTarget(make_tree<PN>(s, counters));
  icp.setSearchMethodSource(make_tree<PN>(s, counters));
  icp.setCorrespondenceEstimation(std::make_shared<BatchedCorrespondences>());
  const bool plane = c.icp.error == IcpError::PointToPlane, lm = c.icp.solver == IcpSolver::Lm;
  using TE = pcl::registration::TransformationEstimation<PN, PN>;
  std::shared_ptr<TE> te;
  if (plane && lm)
    te = std::make_shared<pcl::registration::TransformationEstimationPointToPlane<PN, PN>>();
  else if (plane)
    te = std::make_shared<pcl::registration::TransformationEstimationPointToPlaneLLS<PN, PN>>();
  else if (lm)
    te = std::make_shared<pcl::registration::TransformationEstimationLM<PN, PN>>();
  else
    te = std::make_shared<pcl::registration::TransformationEstimationSVD<PN, PN>>();
  icp.setTransformationEstimation(std::make_shared<GuardedEstimation>(te));
  icp.setMaximumIterations(c.icp.max_iterations);
  icp.setMaxCorrespondenceDistance(c.icp.max_correspondence_distance);
  icp.setTransformationEpsilon(c.icp.transformation_epsilon);
  icp.setEuclideanFitnessEpsilon(c.icp.euclidean_fitness_epsilon);
  icp.setUseReciprocalCorrespondences(c.icp.reciprocal);
  if (c.icp.ransac) {
    auto rej = std::make_shared<pcl::registration::CorrespondenceRejectorSampleConsensus<PN>>();
    rej->setInlierThreshold(c.icp.ransac_threshold);
    rej->setMaximumIterations(c.icp.ransac_iterations);
    rej->setRefineModel(false);
    icp.addCorrespondenceRejector(rej);
  }
  // After each iteration's searches (PCL calls its "visualizer"): the next iteration's jobs are
  // new. PCL also calls it once when it is registered, before any search: that call is skipped.
  std::function<void(const PNCloud&, const pcl::Indices&, const PNCloud&, const pcl::Indices&)> next =
      [rec = s.recorder, registered = false](const PNCloud&, const pcl::Indices&, const PNCloud&,
                                             const pcl::Indices&) mutable {
        if (registered) rec->next_iteration();
        registered = true;
      };
  if (s.recorder) icp.registerVisualizationCallback(next);
  PNCloud aligned;
  IcpOutcome out;
  try {
    icp.align(aligned, guess.cast<float>());
  } catch (const Degenerate& e) {
    out.transform.setConstant(NAN);
    out.iterations = icp.iterations();
    out.stop = "degenerate";
    out.degenerate = e.what();
    out.last_correspondences = icp.last_correspondences();
    return out;
  }
  out.transform = icp.getFinalTransformation().cast<double>();
  out.iterations = icp.iterations();
  out.converged = icp.hasConverged();
  out.stop = stop_reason(icp.getConvergeCriteria()->getConvergenceState());
  out.last_correspondences = icp.last_correspondences();
  return out;
}

// ---------------------------------------------------------------------------------------------
// The stages of this group (stage_table() in stages.hpp).

void run_rejection(PipelineState& s, StageContext& st) {
  const Rejection rej = reject(s.src_d, s.tgt_d, s.pairs, s.c);
  s.r.initial = rej.initial;
  st.info = {{"method", to_string(s.c.rejection.method)},
             {"inliers", rej.inliers.size()},
             {"identity_fallback", rej.fallback}};
}

void run_icp_stage(PipelineState& s, StageContext& st) {
  RegistrationResult& r = s.r;
  const IcpOutcome icp = run_icp(s.src, s.src_n, s.tgt, s.tgt_n, r.initial, s.c, s.rpce_search, st.counters);
  r.transform = icp.transform;
  if (!icp.degenerate.empty()) {
    r.status = "degenerate";
    r.problem = "ICP iteration " + std::to_string(icp.iterations + 1) + ": " + icp.degenerate;
  } else if (!icp.converged) {
    r.status = "not_converged";
    r.problem = "ICP stopped without converging (" + icp.stop + ", " + std::to_string(icp.last_correspondences) +
                " correspondences in its last iteration): the clouds may not overlap, or the initial estimate "
                "is too far off for icp.max_correspondence_distance";
  }
  st.info = {{"iterations", icp.iterations},
             {"converged", icp.converged && icp.degenerate.empty()},
             {"stop", icp.stop},
             {"last_correspondences", icp.last_correspondences}};
  if (s.rpce_search.injects_kth()) st.info["injected"] = {{"error", "kth_nearest"}, {"k", s.c.inject.rpce_kth}};
}

}  // namespace tigris::registration::stages
