#include "pose.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <Eigen/Geometry>

#include "core/input_file.hpp"
#include "core/visible_text.hpp"
#include "sw_ref/cloud.hpp"

namespace tigris {
std::vector<double> numbers_of(std::string text, const std::string& label) {
  for (char& c : text)
    if (c == ',') c = ' ';
  std::istringstream in(text);
  std::vector<double> v;
  std::string word;
  while (in >> word) {
    // strtod, not stod: a subnormal such as 1e-320 is a finite number (stod throws on it).
    char* end = nullptr;
    const double x = std::strtod(word.c_str(), &end);
    const std::size_t used = static_cast<std::size_t>(end - word.c_str());
    if (used != word.size() || !std::isfinite(x))
      throw InputError(label + ": '" + visible_text(word, 40) + "' is not a finite number");
    v.push_back(x);
  }
  return v;
}

namespace {

std::string read_text(const std::string& path) { return read_input(path, "the pose file", kMaxSettingsBytes); }

constexpr double kMaxTranslation = 1e6;  // m

Pose from_rows(const std::vector<double>& v, std::size_t at) {
  Pose t = Pose::Identity();
  const int rows = v.size() - at >= 16 ? 4 : 3;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < 4; ++c) t(r, c) = v[at + static_cast<std::size_t>(4 * r + c)];
  return t;
}

void check_rigid(const Pose& t, const std::string& label) {
  const Eigen::Matrix3d r = t.topLeftCorner<3, 3>();
  const double orth = (r.transpose() * r - Eigen::Matrix3d::Identity()).norm();
  if (orth > 1e-3 || std::abs(r.determinant() - 1.0) > 1e-3 ||
      (t.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9)
    throw InputError(label +
                     ": not a rigid transform (the rotation part is not orthonormal with "
                     "determinant 1, or the last row is not 0 0 0 1)");
  // Beyond this the error arithmetic overflows; no sensor moves 1,000 km between two frames.
  if (t.topRightCorner<3, 1>().cwiseAbs().maxCoeff() > kMaxTranslation)
    throw InputError(label + ": a translation beyond 1e6 m (1,000 km) is not a registration's ground truth");
}

}  // namespace

Pose read_pose_file(const std::string& path) {
  const std::vector<double> v = numbers_of(read_text(path), path);
  if (v.size() != 16 && v.size() != 12)
    throw InputError(path +
                     ": a pose file holds a 4x4 (16 numbers) or a 3x4 (12 numbers) "
                     "row-major transform, found " +
                     std::to_string(v.size()) + " numbers");
  const Pose t = from_rows(v, 0);
  check_rigid(t, path);
  return t;
}

std::vector<Pose> read_kitti_poses(const std::string& path) {
  std::istringstream in(read_text(path));
  std::vector<Pose> poses;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string label = path + ":" + std::to_string(line_no);
    const std::vector<double> v = numbers_of(line, label);
    if (v.empty()) continue;
    if (v.size() != 12)
      throw InputError(label + ": a KITTI pose line holds 12 numbers (3x4 row-major), found " +
                       std::to_string(v.size()));
    poses.push_back(from_rows(v, 0));
    check_rigid(poses.back(), label);
  }
  if (poses.empty()) throw InputError(path + ": no poses in the file");
  return poses;
}

Pose kitti_velo_to_cam() {
  Pose a = Pose::Zero();
  a(0, 1) = -1.0;  // x_cam = -y_velo
  a(1, 2) = -1.0;  // y_cam = -z_velo
  a(2, 0) = 1.0;   // z_cam = x_velo
  a(3, 3) = 1.0;
  return a;
}

Pose kitti_relative_velo_pose(const Pose& cam_pose_source, const Pose& cam_pose_target) {
  const Pose a = kitti_velo_to_cam();
  const Pose cam_rel = cam_pose_target.inverse() * cam_pose_source;  // cam_source -> cam_target
  return a.inverse() * cam_rel * a;
}

Pose kitti_relative_velo_pose(const std::string& poses_path, int source, int target) {
  const std::vector<Pose> poses = read_kitti_poses(poses_path);
  const int n = static_cast<int>(poses.size());
  if (source < 0 || source >= n || target < 0 || target >= n)
    throw InputError(poses_path + ": frames " + std::to_string(source) + " and " + std::to_string(target) +
                     " requested, the file holds poses 0.." + std::to_string(n - 1));
  return kitti_relative_velo_pose(poses[static_cast<std::size_t>(source)], poses[static_cast<std::size_t>(target)]);
}

double rotation_angle_deg(const Pose& t) {
  // atan2 of sin and cos of the angle: accurate for the tiny angles of a good registration
  // (acos of the trace loses them).
  const Eigen::Matrix3d r = t.topLeftCorner<3, 3>();
  const Eigen::Vector3d axis_sin(r(2, 1) - r(1, 2), r(0, 2) - r(2, 0), r(1, 0) - r(0, 1));
  const double c = (r.trace() - 1.0) / 2.0;
  return std::atan2(axis_sin.norm() / 2.0, c) * 180.0 / M_PI;
}

PoseError pose_error(const Pose& ground_truth, const Pose& estimate) {
  const Pose e = ground_truth.inverse() * estimate;
  PoseError out;
  out.translation_m = e.topRightCorner<3, 1>().norm();
  out.rotation_deg = rotation_angle_deg(e);
  out.travelled_m = ground_truth.topRightCorner<3, 1>().norm();
  // Per metre needs motion: a ground truth that does not move leaves them NaN (null, "n/a").
  // A standstill ground truth (a frame paired with itself: KITTI poses differ by 1e-17 m after
  // the camera -> Velodyne products) has no per-metre error; 1 mm is far below any frame step.
  const bool moved = out.travelled_m > PoseError::kStandstillM;
  out.translation_per_m = moved ? out.translation_m / out.travelled_m : NAN;
  out.rotation_deg_per_m = moved ? out.rotation_deg / out.travelled_m : NAN;
  return out;
}

std::size_t equal_steps(const std::vector<Pose>& gt) {
  if (gt.size() < 2) return 0;
  const Pose first = gt[0].inverse() * gt[1];
  const double len = first.topRightCorner<3, 1>().norm(), ang = rotation_angle_deg(first);
  std::size_t n = 1;
  for (std::size_t i = 2; i < gt.size(); ++i, ++n) {
    const Pose step = gt[i - 1].inverse() * gt[i];
    if (std::abs(step.topRightCorner<3, 1>().norm() - len) > 0.002 || std::abs(rotation_angle_deg(step) - ang) > 0.005)
      break;
  }
  return n;
}

std::string equal_steps_warning(std::size_t steps) {
  return "the ground truth's first " + std::to_string(steps) +
         " steps are equal (length to 2 mm, angle to 0.005 deg), as in KITTI 00's first ~15 frames, whose poses "
         "advance a constant 0.86 m while LiDAR registration measures 0.68-0.76 m (docs/registration.md): errors "
         "there may measure the ground truth, not the registration";
}

}  // namespace tigris
