// Poses for the registration pipeline (docs/registration.md): reading a ground-truth transform,
// converting KITTI's camera-frame poses to the Velodyne frame, and the relative pose error.
// Every transform is a 4x4 rigid transform in double precision; "target <- source" means it
// maps source-frame points into the target frame (p_target = T * p_source).
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace tigris {

using Pose = Eigen::Matrix4d;

// The numbers of one text (commas count as spaces); throws InputError naming `label` on a
// word that is not a finite number.
std::vector<double> numbers_of(std::string text, const std::string& label);

// A text file holding a 4x4 (16 numbers) or a KITTI-style 3x4 (12 numbers, last row taken as
// 0 0 0 1), row-major, whitespace or comma separated. Throws InputError naming the file on a
// missing file, another count of numbers, a non-number or a non-rigid rotation part.
Pose read_pose_file(const std::string& path);

// The poses of a KITTI odometry poses.txt: one 3x4 row-major [R|t] a line (cam0 of frame i in
// the frame of pose 0). Throws InputError naming the file (and line) on malformed input.
std::vector<Pose> read_kitti_poses(const std::string& path);

// The Velodyne axes in KITTI's camera axes (KITTI's calibration convention; docs/registration.md):
// x_cam = -y_velo, y_cam = -z_velo, z_cam = x_velo, i.e. p_cam = A * p_velo.
Pose kitti_velo_to_cam();

// Relative pose target <- source in the Velodyne frame from two camera-frame poses of the same
// sequence: T_velo = inv(A) * inv(P_target) * P_source * A.
Pose kitti_relative_velo_pose(const Pose& cam_pose_source, const Pose& cam_pose_target);

// From a poses.txt: the Velodyne-frame pose that maps frame `source` into frame `target`.
Pose kitti_relative_velo_pose(const std::string& poses_path, int source, int target);

// Relative pose error E = inv(T_gt) * T_est: |t_E| in metres and the rotation angle of E in
// degrees; per metre travelled divides both by |t_gt| (NaN when the ground truth does not move:
// a per-metre error of a standstill is undefined, not 0).
struct PoseError {
  double translation_m = 0.0, rotation_deg = 0.0;
  static constexpr double kStandstillM = 1e-3;  // below this the ground truth does not move
  double travelled_m = 0.0;
  double translation_per_m = NAN, rotation_deg_per_m = NAN;
};
PoseError pose_error(const Pose& ground_truth, const Pose& estimate);

// The rotation angle of a rigid transform in degrees (0..180).
double rotation_angle_deg(const Pose& t);

// KITTI 00's first ~15 poses advance in equal steps (0.86 m, 0.139 deg; docs/registration.md):
// the number of steps from the start whose length and rotation equal the first step's to 2 mm
// and 0.005 deg (KITTI 00's stay within 1.2 mm and 0.002 deg). Steady driving can do that too,
// so the warning says "may".
std::size_t equal_steps(const std::vector<Pose>& gt);
constexpr std::size_t kEqualStepsWarn = 5;  // from this many equal steps on, errors there are suspect
// The warning for `steps` equal steps, ending in what it means for the errors measured there.
std::string equal_steps_warning(std::size_t steps);

}  // namespace tigris
