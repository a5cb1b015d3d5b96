#include "kitti_sequence.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <Eigen/LU>

#include "core/input_file.hpp"
#include "sw_ref/cloud.hpp"

namespace tigris {
namespace fs = std::filesystem;

namespace {

// "NNNNNN.bin" (six digits) -> its number; -1 for any other name.
long frame_number(const std::string& name) {
  if (name.size() != 10 || name.compare(6, 4, ".bin") != 0) return -1;
  long n = 0;
  for (int i = 0; i < 6; ++i) {
    if (!std::isdigit(static_cast<unsigned char>(name[static_cast<std::size_t>(i)]))) return -1;
    n = 10 * n + (name[static_cast<std::size_t>(i)] - '0');
  }
  return n;
}

std::string scan_name(long n) {
  char b[32];  // a long of 19 digits and ".bin" fit
  std::snprintf(b, sizeof b, "%06ld.bin", n);
  return b;
}

}  // namespace

Pose read_kitti_calib_tr(const std::string& path) {
  std::istringstream f(read_input(path, "the calibration file", kMaxSettingsBytes));
  std::string line;
  int line_no = 0;
  while (std::getline(f, line)) {
    ++line_no;
    if (line.rfind("Tr:", 0) != 0) continue;
    const std::string label = path + ":" + std::to_string(line_no);
    const std::vector<double> v = numbers_of(line.substr(3), label);
    if (v.size() != 12)
      throw InputError(label + ": Tr holds 12 numbers (3x4 row-major, Velodyne -> cam0), found " +
                       std::to_string(v.size()));
    Pose t = Pose::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) t(r, c) = v[static_cast<std::size_t>(4 * r + c)];
    const Eigen::Matrix3d rot = t.topLeftCorner<3, 3>();
    if ((rot.transpose() * rot - Eigen::Matrix3d::Identity()).norm() > 1e-3 || std::abs(rot.determinant() - 1.0) > 1e-3)
      throw InputError(label + ": Tr is not a rigid transform (its rotation part is not orthonormal)");
    // A Velodyne-to-camera offset is centimetres; 1e300 would pass the rotation check and turn
    // every pose into overflow.
    if (t.topRightCorner<3, 1>().cwiseAbs().maxCoeff() > 100.0)
      throw InputError(label + ": Tr's translation is beyond 100 m: not a sensor-to-camera calibration");
    return t;
  }
  throw InputError(path + ": no 'Tr:' line (the Velodyne -> cam0 calibration)");
}

KittiSequence read_kitti_sequence(const std::string& dir) {
  KittiSequence s;
  s.dir = dir;
  // KITTI's layout has the scans in velodyne/; a folder holding them itself (../shared/data's
  // kitti-00) is read the same way.
  fs::path velo = fs::path(dir) / "velodyne";
  std::error_code ec;
  if (!fs::is_directory(velo, ec)) {
    if (!fs::is_directory(dir, ec))
      throw InputError(dir + ": no such folder (a KITTI sequence holds velodyne/NNNNNN.bin scans)");
    velo = fs::path(dir);
  }
  std::vector<long> numbers;
  for (const auto& e : fs::directory_iterator(velo, ec)) {
    const long n = frame_number(e.path().filename().string());
    if (n >= 0) numbers.push_back(n);
  }
  if (ec) throw InputError(velo.string() + ": cannot list the folder: " + ec.message());
  if (numbers.empty())
    throw InputError(velo.string() +
                     ": no scan (NNNNNN.bin) in the folder (a KITTI sequence holds "
                     "velodyne/NNNNNN.bin scans)");
  std::sort(numbers.begin(), numbers.end());
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    if (numbers[i] != static_cast<long>(i))
      throw InputError((velo / scan_name(static_cast<long>(i))).string() + " is missing: the scans are numbered from " +
                       "000000 without a gap (found " + scan_name(numbers[i]) + " next)");
    s.scans.push_back((velo / scan_name(numbers[i])).string());
  }

  // symlink_status: a broken calib.txt link is the user's file, read (and refused), never
  // taken for "no calibration".
  const fs::path calib = fs::path(dir) / "calib.txt";
  if (fs::exists(fs::symlink_status(calib, ec))) {
    s.velo_to_cam = read_kitti_calib_tr(calib.string());
    s.calibration = calib.string() + " (Tr)";
  } else {
    s.velo_to_cam = kitti_velo_to_cam();
    s.calibration = "no calib.txt: the axis swap x_cam = -y_velo, y_cam = -z_velo, z_cam = x_velo";
  }
  const fs::path poses = fs::path(dir) / "poses.txt";
  if (fs::exists(fs::symlink_status(poses, ec))) {
    const std::vector<Pose> cam = read_kitti_poses(poses.string());
    if (cam.size() < s.scans.size())
      throw InputError(poses.string() + ": " + std::to_string(cam.size()) + " poses for " +
                       std::to_string(s.scans.size()) + " scans in " + velo.string() +
                       " (one pose a scan, frame 0 first)");
    // More poses than scans: a folder holding the first scans of a sequence (../shared/data's
    // KITTI 00 has 2 scans and 6 poses); the first poses are the scans'.
    if (cam.size() > s.scans.size())
      s.note = poses.string() + " holds " + std::to_string(cam.size()) + " poses for " +
               std::to_string(s.scans.size()) + " scans: the first " + std::to_string(s.scans.size()) +
               " are the scans'";
    const Pose inv_tr = s.velo_to_cam.inverse();
    for (const Pose& p : cam) s.poses.push_back(inv_tr * p * s.velo_to_cam);
  }
  return s;
}

void write_kitti_poses(std::ostream& out, const std::vector<Pose>& velo_poses, const Pose& velo_to_cam) {
  const Pose inv_tr = velo_to_cam.inverse();
  char b[40];
  for (const Pose& v : velo_poses) {
    const Pose p = velo_to_cam * v * inv_tr;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) {
        std::snprintf(b, sizeof b, "%.17g", p(r, c));
        out << b << (r == 2 && c == 3 ? '\n' : ' ');
      }
  }
}

}  // namespace tigris
