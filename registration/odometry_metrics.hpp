// KITTI odometry metrics of an estimated trajectory against its ground truth: the segment errors
// of the KITTI odometry devkit (evaluate_odometry.cpp), plus the absolute trajectory error and
// the mean frame-to-frame relative pose error. No PCL: poses in, numbers out.
#pragma once

#include <cstddef>
#include <vector>

#include "workloads/pose.hpp"

namespace tigris::registration {

// Cumulative path length of the positions: dist[0] = 0, dist[i] = dist[i-1] + |t_i - t_{i-1}|
// (empty for no poses).
std::vector<double> trajectory_distances(const std::vector<Pose>& poses);

// One devkit segment: from first_frame over length_m metres of ground-truth path.
struct SegmentError {
  std::size_t first_frame = 0, last_frame = 0;
  double length_m = 0.0;
  double t_err_per_m = 0.0;      // |translation of the segment's pose error| / length
  double r_err_rad_per_m = 0.0;  // rotation angle of the segment's pose error / length
  double speed_m_per_s = 0.0;
};

// The devkit's defaults: segments of 100..800 m, one starting every 10 frames, frames 0.1 s apart.
inline const std::vector<double>& kitti_segment_lengths() {
  static const std::vector<double> lengths{100, 200, 300, 400, 500, 600, 700, 800};
  return lengths;
}

// Every segment as the devkit's calcSequenceErrors lists them (first frame major, then length).
// Throws std::invalid_argument on trajectories of different sizes, a non-finite pose, a length
// that is not finite and positive, step_frames 0 or frame_seconds not finite and positive.
std::vector<SegmentError> sequence_errors(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                                          const std::vector<double>& lengths = kitti_segment_lengths(),
                                          std::size_t step_frames = 10, double frame_seconds = 0.1);

struct LengthMetrics {
  double length_m = 0.0;
  std::size_t segments = 0;
  double t_err_percent = NAN, r_err_deg_per_m = NAN;  // NaN without a segment
};

struct OdometryMetrics {
  std::size_t frames = 0;
  double trajectory_length_m = 0.0;  // ground-truth path length
  std::size_t segments = 0;
  // No segment of the shortest length fits: the t/r errors are NaN, not 0.
  bool too_short = true;
  double t_err_percent = NAN, r_err_deg_per_m = NAN;  // the devkit's sequence averages
  std::vector<LengthMetrics> per_length;              // in the order of `lengths`
  // Absolute trajectory error: RMSE of |t_gt_i - t_est_i| after the best rigid alignment
  // (Umeyama, no scale) of the estimated positions onto the ground truth's.
  double ate_rmse_m = NAN;
  // The same without alignment: the positions as given (KITTI poses start both trajectories
  // at frame 0's pose), so it includes the drift accumulated from the start.
  double ate_anchored_rmse_m = NAN;
  double ate_max_m = NAN;  // largest unaligned position difference
  // Means over consecutive pairs i -> i+1 of pose_error(inv(gt[i])*gt[i+1], inv(est[i])*est[i+1]).
  double mean_rpe_translation_m = NAN, mean_rpe_rotation_deg = NAN;
};

// The metrics of one sequence; fewer than 2 frames give too_short with every error NaN.
// Throws as sequence_errors.
OdometryMetrics odometry_metrics(const std::vector<Pose>& gt, const std::vector<Pose>& est,
                                 const std::vector<double>& lengths = kitti_segment_lengths(),
                                 std::size_t step_frames = 10, double frame_seconds = 0.1);

}  // namespace tigris::registration
