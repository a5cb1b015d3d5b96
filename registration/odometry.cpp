#include "odometry.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <Eigen/LU>

#include "odometry_metrics.hpp"

namespace tigris::registration {

using nlohmann::ordered_json;

namespace {

std::string frame_tag(std::size_t i) {
  char b[16];
  std::snprintf(b, sizeof b, "%06zu", i);
  return b;
}

// NaN (no segment, no ground truth) as null in JSON.
ordered_json number(double x) { return std::isfinite(x) ? ordered_json(x) : ordered_json(); }

// A pair's KD-tree search seconds and searches over its stages.
std::pair<double, double> kd_and_searches(const Report& r) {
  double kd = 0.0, searches = 0.0;
  for (const StageReport& st : r.result.stages) {
    kd += st.kdtree.search_seconds;
    searches += static_cast<double>(st.kdtree.searches);
  }
  return {kd, searches};
}

}  // namespace

Odometry::Odometry(std::size_t first, std::vector<Report> pairs, const std::vector<Pose>& poses, bool accel)
    : first_(first), pairs_(std::move(pairs)), accel_(accel) {
  // Chain: pose of frame first + k + 1 = pose of frame first + k * (its pair's transform).
  est_.push_back(Pose::Identity());
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    if (pairs_[k].degenerate())
      throw std::invalid_argument("pair " + frame_tag(first + k + 1) + " -> " + frame_tag(first + k) +
                                  " is degenerate (no transform: " + pairs_[k].result.problem +
                                  "): the trajectory cannot be chained past it");
    est_.push_back(est_.back() * pairs_[k].result.transform);
  }
  if (!poses.empty()) {
    poses_from_first_.assign(poses.begin() + static_cast<std::ptrdiff_t>(first), poses.end());
    const Pose anchor = poses[first].inverse();
    for (std::size_t i = 0; i < est_.size(); ++i) gt_.push_back(anchor * poses[first + i]);
  }
  for (std::size_t k = 0; k < pairs_.size(); ++k) add_pair(k);
}

// Pair k: its stages into the per-stage sums, its figures into the totals.
void Odometry::add_pair(std::size_t k) {
  const Report& r = pairs_[k];
  for (const StageReport& st : r.result.stages) {
    ordered_json& acc = stages_.try_emplace(st.name, ordered_json::object()).first->second;
    const auto add = [&acc](const char* key, double v) { acc[key] = acc.value(key, 0.0) + v; };
    add("seconds", st.seconds);
    add("kdtree_search_seconds", st.kdtree.search_seconds);
    add("searches", static_cast<double>(st.kdtree.searches));
    if (accel_ && r.in_loop() && !st.search.empty()) {
      const auto& a = st.kdtree.accel;
      add("accelerator_jobs", static_cast<double>(a.jobs));
      add("modeled_kdtree_seconds", modeled_kdtree_seconds(st.kdtree));
      add("modeled_stage_seconds", modeled_stage_seconds(st));
      add("kdtree_energy_pj", a.energy_pj);
      add("fallback_searches", static_cast<double>(a.fallback_searches));
    }
  }
  sum_.seconds += r.result.total_seconds;
  sum_.kd += kd_and_searches(r).first;
  sum_.not_converged += r.result.status != "converged";
  if (accel_) {
    const LoopFigures a = loop_figures(r.result);
    sum_.modeled_kd += a.modeled_kd;
    sum_.modeled_e2e += a.modeled_e2e;
    sum_.energy_pj += a.energy_pj;
    sum_.jobs += a.jobs;
    sum_.sampled_jobs += r.sampled_jobs();
  }
}

void Odometry::write_pairs_csv(std::ostream& out) const {
  out << "pair,source,target,status,seconds,kdtree_seconds,kdtree_share,searches,rpe_translation_m,rpe_rotation_deg";
  if (accel_)
    out << ",modeled_kdtree_seconds,modeled_end_to_end_seconds,kdtree_energy_pj,fallback_searches,sampled_jobs";
  out << '\n';
  char line[512];
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const Report& r = pairs_[k];
    const auto [kd, searches] = kd_and_searches(r);
    const double seconds = r.result.total_seconds;
    double rpe_t = NAN, rpe_r = NAN;
    if (!gt_.empty()) {
      const PoseError e = pose_error(gt_[k].inverse() * gt_[k + 1], est_[k].inverse() * est_[k + 1]);
      rpe_t = e.translation_m;
      rpe_r = e.rotation_deg;
    }
    std::snprintf(line, sizeof line, "%zu,%zu,%zu,%s,%.6f,%.6f,%.4f,%.0f,%.6g,%.6g", k, first_ + k + 1, first_ + k,
                  r.result.status.c_str(), seconds, kd, seconds > 0 ? kd / seconds : 0.0, searches, rpe_t, rpe_r);
    out << line;
    if (accel_) {
      const LoopFigures a = loop_figures(r.result);
      std::snprintf(line, sizeof line, ",%.6g,%.6g,%.6g,%llu,%llu", a.modeled_kd, a.modeled_e2e, a.energy_pj,
                    static_cast<unsigned long long>(a.fallback_searches),
                    static_cast<unsigned long long>(r.sampled_jobs()));
      out << line;
    }
    out << '\n';
  }
}

void Odometry::write_trajectory_csv(std::ostream& out) const {
  // Positions in frame first's Velodyne frame (x forward, y left, z up), for the plots.
  out << "frame,est_x,est_y,est_z,gt_x,gt_y,gt_z\n";
  char line[256];
  for (std::size_t i = 0; i < est_.size(); ++i) {
    const Pose g = gt_.empty() ? Pose::Constant(NAN) : gt_[i];
    std::snprintf(line, sizeof line, "%zu,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", first_ + i, est_[i](0, 3), est_[i](1, 3),
                  est_[i](2, 3), g(0, 3), g(1, 3), g(2, 3));
    out << line;
  }
}

namespace {

// The KITTI devkit's errors, ATE and RPE of `est` against `gt` into m.
void add_kitti_metrics(ordered_json& m, const std::vector<Pose>& gt, const std::vector<Pose>& est, std::size_t first) {
  const OdometryMetrics x = odometry_metrics(gt, est);
  ordered_json lengths = ordered_json::array();
  for (const auto& l : x.per_length)
    lengths.push_back({{"length_m", l.length_m},
                       {"segments", l.segments},
                       {"t_err_percent", number(l.t_err_percent)},
                       {"r_err_deg_per_m", number(l.r_err_deg_per_m)}});
  m["kitti"] = {{"t_err_percent", number(x.t_err_percent)},
                {"r_err_deg_per_m", number(x.r_err_deg_per_m)},
                {"segments", x.segments},
                {"trajectory_length_m", x.trajectory_length_m},
                {"too_short", x.too_short},
                {"per_length", lengths},
                {"how",
                 "the KITTI odometry devkit: segments of 100..800 m of ground-truth path starting every "
                 "10 frames; translational error in % and rotational error in deg/m, averaged over every "
                 "segment"}};
  if (x.too_short)
    m["kitti"]["note"] =
        "the trajectory is shorter than 100 m: no segment fits, so there are no KITTI metrics "
        "(null, not 0)";
  ordered_json segs = ordered_json::array();  // every devkit segment, for the plots
  for (const SegmentError& e : sequence_errors(gt, est))
    segs.push_back({{"first_frame", first + e.first_frame},
                    {"length_m", e.length_m},
                    {"speed_m_per_s", e.speed_m_per_s},
                    {"t_err_percent", 100.0 * e.t_err_per_m},
                    {"r_err_deg_per_m", e.r_err_rad_per_m * 180.0 / M_PI}});
  m["kitti"]["segment_list"] = segs;
  m["ate"] = {{"rmse_m", number(x.ate_rmse_m)},
              {"unaligned_rmse_m", number(x.ate_anchored_rmse_m)},
              {"unaligned_max_m", number(x.ate_max_m)}};
  m["rpe"] = {{"mean_translation_m", number(x.mean_rpe_translation_m)},
              {"mean_rotation_deg", number(x.mean_rpe_rotation_deg)}};
}

}  // namespace

std::string Odometry::add_metrics(ordered_json& m, bool synthetic_truth) const {
  const double n = static_cast<double>(pairs_.size());
  m["not_converged_pairs"] = sum_.not_converged;
  m["totals"] = {{"seconds", sum_.seconds},
                 {"kdtree_search_seconds", sum_.kd},
                 {"kdtree_share", sum_.seconds > 0 ? sum_.kd / sum_.seconds : 0.0}};
  if (accel_)
    m["accelerator"] = {{"modeled_kdtree_seconds", sum_.modeled_kd},
                        {"modeled_end_to_end_seconds", sum_.modeled_e2e},
                        {"kdtree_energy_pj", sum_.energy_pj},
                        {"jobs", sum_.jobs},
                        {"sampled_jobs", sum_.sampled_jobs},  // their figures estimated (docs/sampling.md)
                        {"per_pair_mean",
                         {{"modeled_kdtree_seconds", sum_.modeled_kd / n},
                          {"modeled_end_to_end_seconds", sum_.modeled_e2e / n},
                          {"kdtree_energy_pj", sum_.energy_pj / n}}}};
  // Per stage: the mean over the pairs (with accel, a stage's seconds and KD-tree search seconds
  // hold the simulation's wall time; its modeled figures are the accelerator's).
  ordered_json means = ordered_json::object();
  for (const auto& [name, acc] : stages_) {
    ordered_json mean;
    for (const auto& [key, v] : acc.items()) mean[key] = v.get<double>() / n;
    means[name] = {{"per_pair_mean", mean}};
  }
  m["stages"] = means;
  if (gt_.empty()) {
    m["ground_truth"] = nullptr;
    return "no poses.txt: no error metrics";
  }
  add_kitti_metrics(m, gt_, est_, first_);
  // On every ground-truth pose from frame first, also those past the frames registered; a
  // drive tigris synth wrote has exact poses: equal steps there are steady driving.
  const std::size_t steps = equal_steps(poses_from_first_);
  if (steps >= kEqualStepsWarn && !synthetic_truth) {
    m["ground_truth_warning"] = equal_steps_warning(steps);
    return equal_steps_warning(steps);
  }
  return "";
}

void Odometry::print_summary(std::FILE* out, const ordered_json& m, const std::string& sequence,
                             const std::string& search, const std::string& note) const {
  const Totals& sum = sum_;
  std::fprintf(out, "tigris odometry: %s, frames %zu..%zu (%zu pairs, %zu not converged), search %s\n",
               sequence.c_str(), first_, first_ + pairs(), pairs(), sum.not_converged, search.c_str());
  if (accel_)
    std::fprintf(out, "  registration %.2f s of wall time in all, the accelerator's simulation included\n",
                 sum.seconds);
  else
    std::fprintf(out, "  registration %.2f s in all, KD-tree search %.2f s (%.1f%%)\n", sum.seconds, sum.kd,
                 sum.seconds > 0 ? 100.0 * sum.kd / sum.seconds : 0.0);
  if (accel_) {
    std::fprintf(out, "  on the accelerator (modeled): KD-tree %.4f s, end to end %.3f s, KD-tree energy %.1f uJ\n",
                 sum.modeled_kd, sum.modeled_e2e, sum.energy_pj * 1e-6);
    if (sum.sampled_jobs > 0)
      std::fprintf(out,
                   "  sampled %llu of %llu accelerator jobs: their cycles and energy, and these totals, are estimates "
                   "(--accel-set sim.sampling=off simulates every query)\n",
                   static_cast<unsigned long long>(sum.sampled_jobs), static_cast<unsigned long long>(sum.jobs));
  }
  if (m.contains("kitti")) {
    const auto& k = m["kitti"];
    if (k["too_short"].get<bool>())
      std::fprintf(out, "  KITTI metrics: none, the trajectory (%.1f m) is shorter than 100 m\n",
                   k["trajectory_length_m"].get<double>());
    else
      std::fprintf(out,
                   "  KITTI metrics over %zu segments of %.0f m of path: translation %.3f%%, rotation %.5f deg/m\n",
                   k["segments"].get<std::size_t>(), k["trajectory_length_m"].get<double>(),
                   k["t_err_percent"].get<double>(), k["r_err_deg_per_m"].get<double>());
    std::fprintf(out, "  ATE %.4f m (aligned), %.4f m unaligned; mean RPE %.4f m, %.4f deg per pair\n",
                 m["ate"]["rmse_m"].get<double>(), m["ate"]["unaligned_rmse_m"].get<double>(),
                 m["rpe"]["mean_translation_m"].get<double>(), m["rpe"]["mean_rotation_deg"].get<double>());
  }
  if (!note.empty()) std::fprintf(out, "  note: %s\n", note.c_str());
}

}  // namespace tigris::registration
