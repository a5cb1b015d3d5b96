// KITTI-layout sequence folders (workloads/kitti_sequence.hpp): listing, poses in the
// Velodyne frame through calib.txt's Tr or the axis swap, poses.txt written back, and clear
// errors for a missing scan, a short poses.txt and a bad calibration.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <Eigen/Geometry>

#include "sw_ref/cloud.hpp"
#include "workloads/io/kitti_bin.hpp"
#include "workloads/kitti_sequence.hpp"

using namespace tigris;
namespace fs = std::filesystem;

namespace {

// A fresh folder under the system's temporary directory.
fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("tigris_kitti_seq_" + name);
  fs::remove_all(d);
  fs::create_directories(d / "velodyne");
  return d;
}

void write_scan(const fs::path& d, int n) {
  char name[16];
  std::snprintf(name, sizeof name, "%06d.bin", n);
  const PointCloud cloud{{1.0f, 2.0f, 3.0f}, {4.0f, 5.0f, 6.0f}};
  std::ofstream(d / "velodyne" / name, std::ios::binary) << kitti_bin_bytes(cloud);
}

Pose cam_pose(double x, double yaw) {
  Pose p = Pose::Identity();
  p.topLeftCorner<3, 3>() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  p(2, 3) = x;  // cam0 looks along +z
  p(0, 3) = 0.1 * x;
  return p;
}

void write_poses(const fs::path& file, const std::vector<Pose>& poses) {
  std::ofstream f(file);
  f << std::setprecision(17);
  for (const Pose& p : poses) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) f << p(r, c) << (r == 2 && c == 3 ? "\n" : " ");
  }
}

std::string error_of(const std::string& dir) {
  try {
    read_kitti_sequence(dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("KITTI sequence: scans, poses through calib.txt's Tr, and poses.txt written back", "[odometry]") {
  const fs::path d = fresh_dir("ok");
  for (int i = 0; i < 3; ++i) write_scan(d, i);
  const std::vector<Pose> cam{Pose::Identity(), cam_pose(0.8, 0.01), cam_pose(1.7, 0.03)};
  write_poses(d / "poses.txt", cam);
  // A Tr that is not the axis swap: the swap turned by 0.5 degrees about z.
  const Pose tr = kitti_velo_to_cam() * [] {
    Pose r = Pose::Identity();
    r.topLeftCorner<3, 3>() = Eigen::AngleAxisd(0.5 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    r(0, 3) = 0.27;
    return r;
  }();
  {
    std::ofstream f(d / "calib.txt");
    f << "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nTr:";
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) f << ' ' << std::setprecision(17) << tr(r, c);
    f << '\n';
  }
  const KittiSequence s = read_kitti_sequence(d.string());
  REQUIRE(s.scans.size() == 3);
  CHECK(fs::path(s.scans[2]).filename() == "000002.bin");
  CHECK(s.calibration.find("calib.txt") != std::string::npos);
  CHECK((s.velo_to_cam - tr).norm() < 1e-12);
  REQUIRE(s.poses.size() == 3);
  for (int i = 0; i < 3; ++i) CHECK((s.poses[i] - tr.inverse() * cam[i] * tr).norm() < 1e-12);
  // Written back as cam0 poses, they read back as the same Velodyne poses.
  std::ostringstream text;
  write_kitti_poses(text, s.poses, s.velo_to_cam);
  std::ofstream(d / "poses.txt") << text.str();
  const KittiSequence again = read_kitti_sequence(d.string());
  for (int i = 0; i < 3; ++i) CHECK((again.poses[i] - s.poses[i]).norm() < 1e-12);
  fs::remove_all(d);
}

TEST_CASE("KITTI sequence: without calib.txt the axis swap, as the pair's ground truth", "[odometry]") {
  const fs::path d = fresh_dir("swap");
  for (int i = 0; i < 2; ++i) write_scan(d, i);
  const std::vector<Pose> cam{cam_pose(0.2, 0.0), cam_pose(1.06, 0.002)};
  write_poses(d / "poses.txt", cam);
  const KittiSequence s = read_kitti_sequence(d.string());
  CHECK(s.calibration.find("axis swap") != std::string::npos);
  CHECK((s.velo_to_cam - kitti_velo_to_cam()).norm() == 0.0);
  const Pose relative = s.poses[0].inverse() * s.poses[1];  // frame 1 into frame 0
  CHECK((relative - kitti_relative_velo_pose(cam[1], cam[0])).norm() < 1e-12);
  // More poses than scans (a folder with a sequence's first scans): the first are used, said so.
  write_poses(d / "poses.txt", {cam[0], cam[1], cam_pose(2.0, 0.004)});
  const KittiSequence more = read_kitti_sequence(d.string());
  CHECK(more.poses.size() == 3);
  CHECK((more.poses[1] - s.poses[1]).norm() < 1e-12);
  CHECK_THAT(more.note, Catch::Contains("3 poses for 2 scans"));
  // Without poses.txt: scans only.
  fs::remove(d / "poses.txt");
  CHECK(read_kitti_sequence(d.string()).poses.empty());
  fs::remove_all(d);
}

TEST_CASE("KITTI sequence: a missing scan, a short poses.txt and a bad Tr are errors naming the file", "[odometry]") {
  const fs::path d = fresh_dir("bad");
  CHECK_THAT(error_of((d / "nowhere").string()), Catch::Contains("nowhere: no such folder"));
  CHECK_THAT(error_of(d.string()), Catch::Contains("no scan"));
  for (int i : {0, 1, 3}) write_scan(d, i);
  CHECK_THAT(error_of(d.string()), Catch::Contains("000002.bin is missing") && Catch::Contains("000003.bin next"));
  write_scan(d, 2);
  write_poses(d / "poses.txt", {Pose::Identity(), cam_pose(1, 0)});
  CHECK_THAT(error_of(d.string()), Catch::Contains("poses.txt: 2 poses for 4 scans"));
  write_poses(d / "poses.txt", {Pose::Identity(), cam_pose(1, 0), cam_pose(2, 0), cam_pose(3, 0)});
  std::ofstream(d / "calib.txt") << "P0: 1 0 0 0 0 1 0 0 0 0 1 0\n";
  CHECK_THAT(error_of(d.string()), Catch::Contains("calib.txt: no 'Tr:' line"));
  std::ofstream(d / "calib.txt") << "P0: 1\nTr: 1 0 0 0 0 1 0 0 0 0 1\n";
  CHECK_THAT(error_of(d.string()), Catch::Contains("calib.txt:2: Tr holds 12 numbers") && Catch::Contains("found 11"));
  std::ofstream(d / "calib.txt") << "Tr: 2 0 0 0 0 1 0 0 0 0 1 0\n";
  CHECK_THAT(error_of(d.string()), Catch::Contains("not a rigid transform"));
  std::ofstream(d / "calib.txt") << "Tr: 1 0 0 0 0 1 0 0 0 0 1 nan\n";
  CHECK_THAT(error_of(d.string()), Catch::Contains("'nan' is not a finite number"));
  fs::remove_all(d);
}
