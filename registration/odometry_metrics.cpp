#include "odometry_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace tigris::registration {
namespace {

void check_inputs(const std::vector<Pose>& gt, const std::vector<Pose>& est, const std::vector<double>& lengths,
                  std::size_t step_frames, double frame_seconds) {
  if (gt.size() != est.size())
    throw std::invalid_argument("odometry metrics: the ground truth has " + std::to_string(gt.size()) +
                                " poses, the estimate " + std::to_string(est.size()));
  for (std::size_t i = 0; i < gt.size(); ++i) {
    if (!gt[i].allFinite())
      throw std::invalid_argument("odometry metrics: ground-truth pose " + std::to_string(i) + " is not finite");
    if (!est[i].allFinite())
      throw std::invalid_argument("odometry metrics: estimated pose " + std::to_string(i) + " is not finite");
  }
  for (double len : lengths)
    if (!std::isfinite(len) || len <= 0.0)
      throw std::invalid_argument("odometry metrics: segment length " + std::to_string(len) +
                                  " is not a positive number of metres");
  // A step of 0 would never leave the first frame.
  if (step_frames == 0) throw std::invalid_argument("odometry metrics: step_frames must be at least 1");
  if (!std::isfinite(frame_seconds) || frame_seconds <= 0.0)
    throw std::invalid_argument("odometry metrics: frame_seconds must be positive");
}

Eigen::Vector3d position(const Pose& p) { return p.topRightCorner<3, 1>(); }

// As the devkit's rotationError: the angle from the trace, clamped against rounding.
double rotation_error_rad(const Pose& e) {
  const double d = 0.5 * (e(0, 0) + e(1, 1) + e(2, 2) - 1.0);
  return std::acos(std::clamp(d, -1.0, 1.0));
}

// As the devkit: plain means over the segments (every segment weighs the same), the translation
// in percent and the rotation in degrees per metre; NaN without a segment.
struct Mean {
  std::size_t count = 0;
  double t_percent = NAN, r_deg_per_m = NAN;
};
template <class Keep>
Mean devkit_mean(const std::vector<SegmentError>& errors, Keep keep) {
  Mean m;
  double t = 0.0, r = 0.0;
  for (const SegmentError& e : errors)
    if (keep(e)) {
      t += e.t_err_per_m;
      r += e.r_err_rad_per_m;
      ++m.count;
    }
  if (m.count == 0) return m;
  m.t_percent = 100.0 * t / static_cast<double>(m.count);
  m.r_deg_per_m = r / static_cast<double>(m.count) * 180.0 / M_PI;
  return m;
}

}  // namespace

std::vector<double> trajectory_distances(const std::vector<Pose>& poses) {
  std::vector<double> dist;
  dist.reserve(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i)
    dist.push_back(i == 0 ? 0.0 : dist[i - 1] + (position(poses[i]) - position(poses[i - 1])).norm());
  return dist;
}

std::vector<SegmentError> sequence_errors(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                                          const std::vector<double>& lengths, std::size_t step_frames,
                                          double frame_seconds) {
  check_inputs(gt, est, lengths, step_frames, frame_seconds);
  // As the devkit (which uses float; double here): segments are measured on the ground truth.
  const std::vector<double> dist = trajectory_distances(gt);
  std::vector<SegmentError> out;
  for (std::size_t first = 0; first < gt.size(); first += step_frames) {
    for (double len : lengths) {
      // The devkit's lastFrameFromSegmentLength: the first frame strictly beyond `len`.
      const auto beyond =
          std::upper_bound(dist.begin() + static_cast<std::ptrdiff_t>(first), dist.end(), dist[first] + len);
      if (beyond == dist.end()) continue;
      const auto last = static_cast<std::size_t>(beyond - dist.begin());
      const Pose delta_gt = gt[first].inverse() * gt[last];
      const Pose delta_est = est[first].inverse() * est[last];
      const Pose error = delta_est.inverse() * delta_gt;
      const double frames = static_cast<double>(last - first + 1);
      out.push_back({first, last, len, error.topRightCorner<3, 1>().norm() / len, rotation_error_rad(error) / len,
                     len / (frame_seconds * frames)});
    }
  }
  return out;
}

OdometryMetrics odometry_metrics(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                                 const std::vector<double>& lengths, std::size_t step_frames, double frame_seconds) {
  const std::vector<SegmentError> errors = sequence_errors(gt, est, lengths, step_frames, frame_seconds);
  OdometryMetrics m;
  m.frames = gt.size();
  const std::vector<double> dist = trajectory_distances(gt);
  m.trajectory_length_m = dist.empty() ? 0.0 : dist.back();
  m.segments = errors.size();

  const Mean all = devkit_mean(errors, [](const SegmentError&) { return true; });
  m.t_err_percent = all.t_percent;
  m.r_err_deg_per_m = all.r_deg_per_m;
  for (double len : lengths) {
    const Mean one = devkit_mean(errors, [len](const SegmentError& e) { return e.length_m == len; });
    m.per_length.push_back({len, one.count, one.t_percent, one.r_deg_per_m});
  }
  // Segments fit the shortest length first, so none of it means none at all.
  m.too_short = m.segments == 0;
  if (gt.size() < 2) return m;

  const Eigen::Index n = static_cast<Eigen::Index>(gt.size());
  Eigen::Matrix3Xd p_gt(3, n), p_est(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    p_gt.col(i) = position(gt[static_cast<std::size_t>(i)]);
    p_est.col(i) = position(est[static_cast<std::size_t>(i)]);
  }
  const Eigen::Matrix4d align = Eigen::umeyama(p_est, p_gt, false);  // est -> gt, rigid
  const Eigen::Matrix3Xd aligned = (align.topLeftCorner<3, 3>() * p_est).colwise() + align.topRightCorner<3, 1>();
  const Eigen::VectorXd d_aligned = (p_gt - aligned).colwise().norm();
  const Eigen::VectorXd d_raw = (p_gt - p_est).colwise().norm();
  m.ate_rmse_m = std::sqrt(d_aligned.squaredNorm() / static_cast<double>(n));
  m.ate_anchored_rmse_m = std::sqrt(d_raw.squaredNorm() / static_cast<double>(n));
  m.ate_max_m = d_raw.maxCoeff();

  double rpe_t = 0.0, rpe_r = 0.0;
  for (std::size_t i = 0; i + 1 < gt.size(); ++i) {
    const PoseError e = pose_error(gt[i].inverse() * gt[i + 1], est[i].inverse() * est[i + 1]);
    rpe_t += e.translation_m;
    rpe_r += e.rotation_deg;
  }
  m.mean_rpe_translation_m = rpe_t / static_cast<double>(gt.size() - 1);
  m.mean_rpe_rotation_deg = rpe_r / static_cast<double>(gt.size() - 1);
  return m;
}

}  // namespace tigris::registration
