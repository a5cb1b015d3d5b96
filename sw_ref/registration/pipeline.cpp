// The pipeline's stage order, timing and per-stage search counters (pipeline.hpp).
#include <chrono>
#include <stdexcept>

#include "stages.hpp"

namespace tigris::registration {
namespace {

using Clock = std::chrono::steady_clock;
using namespace stages;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

Cloud::Ptr to_pcl(const PointCloud& c) {
  auto out = std::make_shared<Cloud>();
  out->reserve(c.size());
  for (const Point3& p : c) out->push_back(pcl::PointXYZ(p.x, p.y, p.z));
  return out;
}

// The search settings of a stage: approximate search only where the paper approximates
// (normals, RPCE); elsewhere the approx back-end searches exactly on the golden model.
SearchSettings settings_for(const PipelineConfig& c, bool approximable, const PipelineHooks& hooks) {
  SearchSettings s;
  s.budget = hooks.budget;
  s.recorder = hooks.recorder;
  s.backend = c.search.backend;
  if (s.backend == Backend::Approx && !approximable) s.backend = Backend::Exact;
  if (s.backend == Backend::Flann && hooks.accelerator)
    throw std::invalid_argument("the accelerator in the loop runs the golden model's searches: search.backend must be "
                                "exact or approx, not flann");
  s.accelerator = hooks.accelerator;
  s.top_height = c.search.top_height;
  s.nn_thd = static_cast<float>(c.search.nn_thd);
  s.radius_thd = static_cast<float>(c.search.radius_thd);
  s.leader_capacity = c.search.leader_capacity;
  s.leader_width = c.search.leader_width;
  s.leader_scope = c.search.leader_scope;
  s.leader_in_flight = c.search.leader_in_flight;
  return s;
}

// Times one stage and collects its counters into the result.
class StageRun {
 public:
  StageRun(RegistrationResult& r, const std::string& name, const StageCallback& cb, const SearchSettings* s)
      : result_(r), counters_(std::make_shared<SearchCounters>()), t0_(Clock::now()) {
    report_.name = name;
    if (s) report_.search = to_string(s->backend);
    if (cb) cb(name);
  }
  const Counters& counters() const { return counters_; }
  nlohmann::json& info() { return report_.info; }
  void done() {
    report_.seconds = seconds_since(t0_);
    report_.kdtree = *counters_;
    result_.stages.push_back(report_);
  }

 private:
  RegistrationResult& result_;
  Counters counters_;
  StageReport report_;
  Clock::time_point t0_;
};

}  // namespace

RegistrationResult register_clouds(const PointCloud& source_points, const PointCloud& target_points,
                                   const PipelineConfig& c, const PipelineHooks& hooks) {
  const auto t_all = Clock::now();
  RegistrationResult r;
  validate(c, "registration configuration");
  const SearchSettings exact = settings_for(c, false, hooks),
                       approximable = settings_for(c, true, hooks);
  // Every stage announces itself to the caller and to the trace recorder.
  const StageCallback on_stage = [&hooks](const std::string& stage) {
    if (hooks.recorder) hooks.recorder->begin_stage(stage);
    if (hooks.on_stage) hooks.on_stage(stage);
  };
  // Error injection only on the paper's injected searches: normal estimation (radius) and RPCE.
  SearchSettings normals_s = approximable, rpce_s = approximable;
  normals_s.shell_inner = static_cast<float>(c.inject.normals_shell_inner);
  normals_s.shell_outer = static_cast<float>(c.inject.normals_shell_outer);
  rpce_s.inject_kth = c.inject.rpce_kth;
  Cloud::Ptr src = to_pcl(source_points), tgt = to_pcl(target_points);

  if (c.outlier_removal.enabled) {
    StageRun st(r, "outlier_removal", on_stage, &exact);
    const std::size_t ns = src->size(), nt = tgt->size();
    src = remove_outliers(src, c, exact, st.counters());
    tgt = remove_outliers(tgt, c, exact, st.counters());
    st.info() = {{"source_points", ns}, {"source_kept", src->size()}, {"target_points", nt}, {"target_kept", tgt->size()}};
    st.done();
  }

  Normals::Ptr src_n, tgt_n;
  {
    StageRun st(r, "normals", on_stage, &normals_s);
    const std::size_t ds = estimate_normals(src, src_n, c, normals_s, st.counters());
    const std::size_t dt = estimate_normals(tgt, tgt_n, c, normals_s, st.counters());
    st.info() = {{"source_without_normal", ds}, {"target_without_normal", dt},
                 {"source_points", src->size()}, {"target_points", tgt->size()}};
    if (normals_s.injects_shell())
      st.info()["injected"] = {{"error", "shell"},
                               {"inner_m", c.inject.normals_shell_inner},
                               {"outer_m", c.inject.normals_shell_outer},
                               {"instead_of_radius_m", c.normals.radius}};
    st.done();
  }
  if (src->size() < 3 || tgt->size() < 3)
    throw std::runtime_error("registration: fewer than 3 points with a normal are left (source " +
                             std::to_string(src->size()) + ", target " + std::to_string(tgt->size()) +
                             "); is normals.radius too small for these clouds?");

  Cloud::Ptr src_k, tgt_k;
  {
    const bool searches = c.keypoints.method == KeypointMethod::Harris3d;
    StageRun st(r, "keypoints", on_stage, searches ? &exact : nullptr);
    src_k = detect_keypoints(src, src_n, c, exact, st.counters());
    tgt_k = detect_keypoints(tgt, tgt_n, c, exact, st.counters());
    st.info() = {{"method", to_string(c.keypoints.method)}, {"source", src_k->size()}, {"target", tgt_k->size()}};
    if (c.keypoints.method == KeypointMethod::Sift) st.info()["note"] = "PCL's SIFT searches its own FLANN trees (not counted)";
    st.done();
  }

  Descriptors src_d, tgt_d;
  {
    StageRun st(r, "descriptors", on_stage, &exact);
    src_d = describe(src_k, src, src_n, c, exact, st.counters());
    tgt_d = describe(tgt_k, tgt, tgt_n, c, exact, st.counters());
    st.info() = {{"method", to_string(c.descriptors.method)}, {"source", src_d.keypoints->size()},
                 {"target", tgt_d.keypoints->size()}, {"source_dropped", src_d.dropped},
                 {"target_dropped", tgt_d.dropped}};
    st.done();
  }

  pcl::Correspondences pairs;
  {
    StageRun st(r, "kpce", on_stage, nullptr);
    pairs = match_features(src_d, tgt_d, c.kpce.reciprocal);
    st.info() = {{"correspondences", pairs.size()}, {"reciprocal", c.kpce.reciprocal},
                 {"feature_queries", src_d.keypoints->size() + (c.kpce.reciprocal ? tgt_d.keypoints->size() : 0)},
                 {"feature_search", "exact feature-space KD-tree (PCL FLANN), not the 3D plug-in"}};
    st.done();
  }

  {
    StageRun st(r, "rejection", on_stage, nullptr);
    const Rejection rej = reject(src_d, tgt_d, pairs, c);
    r.initial = rej.initial;
    st.info() = {{"method", to_string(c.rejection.method)}, {"inliers", rej.inliers.size()},
                 {"identity_fallback", rej.fallback}};
    st.done();
  }

  {
    StageRun st(r, "icp", on_stage, &rpce_s);
    const IcpOutcome icp = run_icp(src, src_n, tgt, tgt_n, r.initial, c, rpce_s, st.counters());
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
    st.info() = {{"iterations", icp.iterations}, {"converged", icp.converged && icp.degenerate.empty()}, {"stop", icp.stop},
                 {"last_correspondences", icp.last_correspondences}};
    if (rpce_s.injects_kth()) st.info()["injected"] = {{"error", "kth_nearest"}, {"k", c.inject.rpce_kth}};
    st.done();
  }
  r.total_seconds = seconds_since(t_all);
  return r;
}

}  // namespace tigris::registration
