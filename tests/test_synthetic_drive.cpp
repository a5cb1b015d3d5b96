// The synthetic drive (workloads/synthetic/drive.hpp): determinism, a short drive as the prefix of a
// long one, the car's kinematics (speeds, accelerations, turns, stops), rigid poses, and scans
// that agree with the poses (the road under consecutive scans, moved by the ground truth).
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "test_util.hpp"
#include "workloads/synthetic/drive.hpp"

using tigris::test::bits;
using tigris::test::same_bits;

namespace {

using tigris::DriveConfig;
using tigris::DriveFrame;
using tigris::PointCloud;
using tigris::SyntheticDrive;

DriveConfig small(int frames, std::uint64_t seed = 1) {
  DriveConfig c;
  c.frames = frames;
  c.seed = seed;
  c.azimuth_steps = 360;  // 1 degree: fast, same geometry
  return c;
}

// Least-squares plane z = a x + b y + c through the road in front of the car (the lane: no
// parked car, no pole), points given in frame-i coordinates by `to_i`.
std::array<double, 3> road_plane(const PointCloud& scan, const std::array<double, 12>& to_i) {
  double s[3][3] = {}, r[3] = {};
  for (const auto& p : scan) {
    const double x = (to_i[0] * p.x + to_i[1] * p.y) + to_i[2] * p.z + to_i[3];
    const double y = (to_i[4] * p.x + to_i[5] * p.y) + to_i[6] * p.z + to_i[7];
    const double z = (to_i[8] * p.x + to_i[9] * p.y) + to_i[10] * p.z + to_i[11];
    if (!(x > 5.0 && x < 15.0 && std::abs(y) < 2.5 && z < -1.4)) continue;
    const double v[3] = {x, y, 1.0};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) s[i][j] += v[i] * v[j];
      r[i] += v[i] * z;
    }
  }
  // Cramer's rule on the 3x3 normal equations.
  const auto det = [](const double m[3][3]) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  const double d = det(s);
  std::array<double, 3> out{};
  for (int k = 0; k < 3; ++k) {
    double m[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[i][j] = j == k ? r[i] : s[i][j];
    out[static_cast<std::size_t>(k)] = det(m) / d;
  }
  return out;
}

// inv(a) * b for rigid 3x4 transforms.
std::array<double, 12> between(const std::array<double, 12>& a, const std::array<double, 12>& b) {
  std::array<double, 12> r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) {
      double v = 0.0;
      for (int k = 0; k < 3; ++k) v += a[4 * k + i] * (j < 3 ? b[4 * k + j] : b[4 * k + 3] - a[4 * k + 3]);
      r[4 * i + j] = v;
    }
  return r;
}

}  // namespace

TEST_CASE("synthetic drive: the same seed gives the same bits, another seed another drive", "[synthetic]") {
  const SyntheticDrive a(small(3)), b(small(3)), c(small(3, 2));
  CHECK(same_bits(a.scan(2), b.scan(2)));
  CHECK(a.frames()[2].pose == b.frames()[2].pose);
  CHECK_FALSE(same_bits(a.scan(2), c.scan(2)));
  CHECK(a.scan(2).size() > 15000);  // 64 x 360 rays, most of them return
}

TEST_CASE("synthetic drive: a shorter drive is the start of a longer one", "[synthetic]") {
  const SyntheticDrive short_drive(small(5)), long_drive(small(120));
  for (int i = 0; i < 5; ++i) {
    CHECK(short_drive.frames()[static_cast<std::size_t>(i)].pose ==
          long_drive.frames()[static_cast<std::size_t>(i)].pose);
    CHECK(short_drive.frames()[static_cast<std::size_t>(i)].speed_m_per_s ==
          long_drive.frames()[static_cast<std::size_t>(i)].speed_m_per_s);
  }
  CHECK(same_bits(short_drive.scan(4), long_drive.scan(4)));
}

TEST_CASE("synthetic drive: the car drives 0-15 m/s, brakes and accelerates gently, turns and stops", "[synthetic]") {
  const SyntheticDrive drive(small(300));
  const std::vector<DriveFrame>& f = drive.frames();
  REQUIRE(f.size() == 300);
  int stopped = 0, longest_stop = 0;
  double max_yaw_deg = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const DriveFrame& x = f[i];
    CHECK(x.speed_m_per_s >= 0.0);
    CHECK(x.speed_m_per_s <= 15.0);
    CHECK(x.time_s == Approx(0.1 * static_cast<double>(i)));
    // Rigid: R^T R = I.
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        double dot = 0.0;
        for (int k = 0; k < 3; ++k)
          dot += x.pose[static_cast<std::size_t>(4 * k + r)] * x.pose[static_cast<std::size_t>(4 * k + c)];
        CHECK(std::abs(dot - (r == c ? 1.0 : 0.0)) < 1e-12);
      }
    stopped = x.speed_m_per_s == 0.0 ? stopped + 1 : 0;
    longest_stop = std::max(longest_stop, stopped);
    max_yaw_deg = std::max(max_yaw_deg, std::abs(std::atan2(x.pose[4], x.pose[0])) * 180.0 / M_PI);
    if (i == 0) continue;
    const DriveFrame& p = f[i - 1];
    CHECK(std::abs(x.speed_m_per_s - p.speed_m_per_s) <= 0.1 * 3.0);  // planned 2.5 m/s^2, a little more at a stop
    const double moved = std::hypot(x.pose[3] - p.pose[3], std::hypot(x.pose[7] - p.pose[7], x.pose[11] - p.pose[11]));
    const double along = x.distance_m - p.distance_m;
    CHECK(along >= 0.0);
    CHECK(moved <= along * 1.002 + 1e-9);  // a chord of the path (the sensor sits above the road)
    CHECK(moved >= along * 0.99 - 1e-9);
  }
  CHECK(longest_stop >= 10);  // a stop at a crossing, a second or more
  CHECK(max_yaw_deg > 80.0);  // a turn into a crossing street
  CHECK(f.back().distance_m > 200.0);
  CHECK(drive.summary().max_grade > 0.005);  // the road is not flat
  CHECK(drive.summary().max_grade < 0.1);
}

TEST_CASE("synthetic drive: the road under two consecutive scans agrees through the ground truth", "[synthetic]") {
  DriveConfig c = small(41);
  c.range_noise_m = 0.0f;
  const SyntheticDrive drive(c);
  const std::array<double, 12> identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  for (const int i : {0, 20, 39}) {
    const auto& pi = drive.frames()[static_cast<std::size_t>(i)].pose;
    const auto& pj = drive.frames()[static_cast<std::size_t>(i + 1)].pose;
    const std::array<double, 3> own = road_plane(drive.scan(i), identity);
    const std::array<double, 3> next = road_plane(drive.scan(i + 1), between(pi, pj));
    INFO("frame " << i << ": own plane " << own[0] << " " << own[1] << " " << own[2] << ", next " << next[0] << " "
                  << next[1] << " " << next[2]);
    CHECK(own[2] == Approx(-1.73).margin(0.01));  // the sensor 1.73 m above the road
    CHECK(std::abs(own[0] - next[0]) < 3e-5);     // slope along: 0.002 degrees
    CHECK(std::abs(own[1] - next[1]) < 3e-5);
    CHECK(std::abs(own[2] - next[2]) < 3e-4);  // height: 0.3 mm
  }
}

TEST_CASE("synthetic drive: impossible settings are refused", "[synthetic]") {
  DriveConfig c = small(0);
  CHECK_THROWS_WITH(SyntheticDrive(c), Catch::Contains("frames must be in 1..20000"));
  c = small(3);
  c.max_range_m = 1.0f;
  CHECK_THROWS_WITH(SyntheticDrive(c), Catch::Contains("min_range_m < max_range_m"));
  const SyntheticDrive d(small(3));
  CHECK_THROWS_WITH(d.scan(3), Catch::Contains("no frame 3"));
}
