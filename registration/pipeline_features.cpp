// Pipeline features: descriptors (FPFH, SHOT with reference frames computed through the plug-in)
// and KPCE, the key-point correspondences in feature space.
#include <cmath>
#include <stdexcept>

#include <pcl/features/fpfh.h>
#include <pcl/features/shot.h>
#include <pcl/features/shot_lrf.h>
#include <pcl/registration/correspondence_estimation.h>

#include "stages.hpp"

namespace tigris::registration::stages {
namespace {

template <class Signature>
bool finite(const Signature& f) {
  for (float x : f.histogram)
    if (!std::isfinite(x)) return false;
  return true;
}
bool finite(const pcl::SHOT352& f) {
  for (float x : f.descriptor)
    if (!std::isfinite(x)) return false;
  for (float x : f.rf)
    if (!std::isfinite(x)) return false;
  return true;
}

// Keeps the key points whose feature is finite, both clouds aligned.
template <class Feature>
void keep_finite(Descriptors& d, const Cloud::ConstPtr& keypoints, pcl::PointCloud<Feature>& all,
                 typename pcl::PointCloud<Feature>::Ptr& out) {
  d.keypoints = std::make_shared<Cloud>();
  out = std::make_shared<pcl::PointCloud<Feature>>();
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (!finite(all[i])) continue;
    d.keypoints->push_back((*keypoints)[i]);
    out->push_back(all[i]);
  }
  d.dropped = all.size() - out->size();
}

template <class Feature>
pcl::Correspondences match(const typename pcl::PointCloud<Feature>::Ptr& source,
                           const typename pcl::PointCloud<Feature>::Ptr& target, bool reciprocal) {
  // Feature space is searched exactly (the paper: approximate KPCE costs accuracy) with PCL's
  // own KD-tree on the features, not the 3D plug-in.
  pcl::registration::CorrespondenceEstimation<Feature, Feature> est;
  est.setInputSource(source);
  est.setInputTarget(target);
  pcl::Correspondences out;
  if (reciprocal)
    est.determineReciprocalCorrespondences(out);
  else
    est.determineCorrespondences(out);
  return out;
}

}  // namespace

Descriptors describe(const Cloud::ConstPtr& keypoints, const Cloud::ConstPtr& surface, const Normals::ConstPtr& normals,
                     const PipelineConfig& c, const SearchSettings& s, const Counters& counters) {
  Descriptors d;
  const double r = c.descriptors.radius;
  if (c.descriptors.method == DescriptorMethod::Fpfh) {
    pcl::FPFHEstimation<pcl::PointXYZ, pcl::Normal, pcl::FPFHSignature33> est;  // never the OMP one
    est.setInputCloud(keypoints);
    est.setSearchSurface(surface);
    est.setInputNormals(normals);
    // In the loop, PCL's three passes are three jobs: the key points; the SPFH pass over every
    // neighbour the first pass found (PCL's std::set: ascending surface indices); the key
    // points again.
    const auto tree = make_tree<pcl::PointXYZ>(s, counters);
    tree->expect_queries(*keypoints);
    TigrisKdTree<pcl::PointXYZ>* t = tree.get();  // not the shared pointer: the tree keeps these
    tree->then_expect([t, surface] {
      const pcl::Indices neighbors = t->last_job_neighbors();
      t->expect_queries(*surface, &neighbors);
    });
    tree->then_expect([t, keypoints] { t->expect_queries(*keypoints); });
    est.setSearchMethod(tree);
    est.setRadiusSearch(r);
    pcl::PointCloud<pcl::FPFHSignature33> all;
    est.compute(all);
    keep_finite(d, keypoints, all, d.fpfh);
  } else {
    // SHOT's own reference-frame estimation would make its own search object: the frames are
    // computed here with the plug-in and handed over.
    auto tree = make_tree<pcl::PointXYZ>(s, counters);
    tree->expect_queries(*keypoints);  // in the loop: the frames' searches (then SHOT's, below)
    pcl::SHOTLocalReferenceFrameEstimation<pcl::PointXYZ, pcl::ReferenceFrame> lrf;
    lrf.setInputCloud(keypoints);
    lrf.setSearchSurface(surface);
    lrf.setSearchMethod(tree);
    lrf.setRadiusSearch(r);
    auto frames = std::make_shared<pcl::PointCloud<pcl::ReferenceFrame>>();
    lrf.compute(*frames);
    // SHOT searches only the key points whose frame is finite (PCL 1.13, shot.hpp): those are
    // its job.
    pcl::Indices framed;
    for (std::size_t i = 0; i < frames->size() && i < keypoints->size(); ++i) {
      const pcl::ReferenceFrame& f = (*frames)[i];
      if (std::isfinite(f.x_axis[0]) && std::isfinite(f.y_axis[0]) && std::isfinite(f.z_axis[0]))
        framed.push_back(static_cast<pcl::index_t>(i));
    }
    tree->expect_queries(*keypoints, &framed);
    pcl::SHOTEstimation<pcl::PointXYZ, pcl::Normal, pcl::SHOT352> est;  // never the OMP one
    est.setInputCloud(keypoints);
    est.setSearchSurface(surface);
    est.setInputNormals(normals);
    est.setInputReferenceFrames(frames);
    est.setSearchMethod(tree);
    est.setRadiusSearch(r);
    pcl::PointCloud<pcl::SHOT352> all;
    est.compute(all);
    keep_finite(d, keypoints, all, d.shot);
  }
  return d;
}

pcl::Correspondences match_features(const Descriptors& source, const Descriptors& target, bool reciprocal) {
  if (source.keypoints->empty() || target.keypoints->empty()) return {};
  if (source.fpfh) return match<pcl::FPFHSignature33>(source.fpfh, target.fpfh, reciprocal);
  return match<pcl::SHOT352>(source.shot, target.shot, reciprocal);
}

// ---------------------------------------------------------------------------------------------
// The stages of this group (stage_table() in stages.hpp).

void run_descriptors(PipelineState& s, StageContext& st) {
  s.src_d = describe(s.src_k, s.src, s.src_n, s.c, s.exact, st.counters);
  s.tgt_d = describe(s.tgt_k, s.tgt, s.tgt_n, s.c, s.exact, st.counters);
  st.info = {{"method", to_string(s.c.descriptors.method)},
             {"source", s.src_d.keypoints->size()},
             {"target", s.tgt_d.keypoints->size()},
             {"source_dropped", s.src_d.dropped},
             {"target_dropped", s.tgt_d.dropped}};
}

void run_kpce(PipelineState& s, StageContext& st) {
  s.pairs = match_features(s.src_d, s.tgt_d, s.c.kpce.reciprocal);
  st.info = {{"correspondences", s.pairs.size()},
             {"reciprocal", s.c.kpce.reciprocal},
             {"feature_queries", s.src_d.keypoints->size() + (s.c.kpce.reciprocal ? s.tgt_d.keypoints->size() : 0)},
             {"feature_search", "exact feature-space KD-tree (PCL FLANN), not the 3D plug-in"}};
}

}  // namespace tigris::registration::stages
