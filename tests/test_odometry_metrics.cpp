// The KITTI odometry metrics (registration/odometry_metrics.hpp) on trajectories whose
// errors are computed by hand: segment selection and counts, the devkit's averages, the
// too-short case, ATE with and without alignment, mean RPE and bad input.
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "registration/odometry_metrics.hpp"

using namespace tigris;
using namespace tigris::registration;
using Catch::Matchers::Contains;

namespace {

Pose pose(double yaw_rad, double x, double y, double z = 0.0) {
  Pose p = Pose::Identity();
  p.topLeftCorner<3, 3>() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.topRightCorner<3, 1>() = Eigen::Vector3d(x, y, z);
  return p;
}

// Along x, `step` metres a frame, no rotation.
std::vector<Pose> straight(std::size_t frames, double step) {
  std::vector<Pose> v;
  for (std::size_t i = 0; i < frames; ++i) v.push_back(pose(0.0, step * static_cast<double>(i), 0.0));
  return v;
}

// A circle of radius r driven at a constant yaw rate of w rad a frame, heading along the tangent.
std::vector<Pose> arc(std::size_t frames, double r = 50.0, double w = 0.02) {
  std::vector<Pose> v;
  for (std::size_t i = 0; i < frames; ++i) {
    const double a = w * static_cast<double>(i);
    v.push_back(pose(a, r * std::sin(a), r * (1.0 - std::cos(a))));
  }
  return v;
}

}  // namespace

TEST_CASE("odometry: trajectory distances add the step lengths", "[odometry]") {
  // Steps of 5 (3-4-5), 12 and 0 m.
  const std::vector<Pose> p{pose(0, 0, 0), pose(0.3, 3, 4), pose(-1.0, 3, 4, 12), pose(2.0, 3, 4, 12)};
  const std::vector<double> d = trajectory_distances(p);
  REQUIRE(d.size() == 4);
  CHECK(d[0] == 0.0);
  CHECK(d[1] == Approx(5.0));
  CHECK(d[2] == Approx(17.0));
  CHECK(d[3] == Approx(17.0));
  CHECK(trajectory_distances({}).empty());
}

TEST_CASE("odometry: straight line with 1 percent long steps - segments and devkit averages", "[odometry]") {
  // Ground truth 1 m a frame, 301 frames (dist[i] = i); the estimate 1.01 m a frame. A segment of
  // length L ends at the first frame strictly beyond L: last = first + L + 1, so it fits when
  // first <= 299 - L. L = 100: first 0..190 (20); L = 200: first 0..90 (10); longer: none.
  // Its pose error: gt delta L+1, estimate 1.01 (L+1), t_err = 0.01 (L+1).
  const std::vector<Pose> gt = straight(301, 1.0), est = straight(301, 1.01);
  const std::vector<SegmentError> s = sequence_errors(gt, est);
  REQUIRE(s.size() == 30);
  CHECK(s[0].first_frame == 0);
  CHECK(s[0].last_frame == 101);
  CHECK(s[0].length_m == 100.0);
  CHECK(s[0].t_err_per_m == Approx(1.01 / 100).epsilon(1e-9));
  CHECK(s[0].r_err_rad_per_m == Approx(0.0).margin(1e-12));
  CHECK(s[0].speed_m_per_s == Approx(100.0 / (0.1 * 102)));  // 9.8039 m/s
  CHECK(s[1].first_frame == 0);
  CHECK(s[1].last_frame == 201);
  CHECK(s[1].t_err_per_m == Approx(2.01 / 200).epsilon(1e-9));
  CHECK(s.back().first_frame == 190);
  CHECK(s.back().last_frame == 291);
  CHECK(s.back().length_m == 100.0);

  const OdometryMetrics m = odometry_metrics(gt, est);
  CHECK(m.frames == 301);
  CHECK(m.trajectory_length_m == 300.0);
  CHECK(m.segments == 30);
  CHECK_FALSE(m.too_short);
  // 100 * (20 * 0.0101 + 10 * 0.01005) / 30 = 1.008333 %.
  CHECK(m.t_err_percent == Approx(100.0 * 0.3025 / 30).epsilon(1e-9));
  CHECK(m.r_err_deg_per_m == Approx(0.0).margin(1e-12));
  REQUIRE(m.per_length.size() == 8);
  CHECK(m.per_length[0].length_m == 100.0);
  CHECK(m.per_length[0].segments == 20);
  CHECK(m.per_length[0].t_err_percent == Approx(1.01).epsilon(1e-9));
  CHECK(m.per_length[1].segments == 10);
  CHECK(m.per_length[1].t_err_percent == Approx(1.005).epsilon(1e-9));
  for (std::size_t k = 2; k < 8; ++k) {
    CHECK(m.per_length[k].segments == 0);
    CHECK(std::isnan(m.per_length[k].t_err_percent));
    CHECK(std::isnan(m.per_length[k].r_err_deg_per_m));
  }
  // Every frame-to-frame step is 1 cm long, no rotation.
  CHECK(m.mean_rpe_translation_m == Approx(0.01).epsilon(1e-9));
  CHECK(m.mean_rpe_rotation_deg == Approx(0.0).margin(1e-12));
  // Unaligned the error is 0.01 i: RMSE 0.01 sqrt(mean i^2) = 0.01 sqrt(30050), max 3 m.
  // Aligned (a shift along x to the centroids) it is 0.01 (i - 150): 0.01 sqrt((301^2 - 1) / 12).
  CHECK(m.ate_anchored_rmse_m == Approx(0.01 * std::sqrt(30050.0)).epsilon(1e-9));
  CHECK(m.ate_max_m == Approx(3.0).epsilon(1e-9));
  CHECK(m.ate_rmse_m == Approx(0.01 * std::sqrt(7550.0)).epsilon(1e-9));
}

TEST_CASE("odometry: an exact estimate of a constant yaw rate arc has no error", "[odometry]") {
  // Chord 100 sin(0.01) = 0.99998 m a frame: L = 100 ends at first + 101, L = 200 at first + 201
  // (the same 20 + 10 segments as the straight line).
  const std::vector<Pose> gt = arc(301);
  const OdometryMetrics m = odometry_metrics(gt, gt);
  CHECK(m.segments == 30);
  CHECK(m.trajectory_length_m == Approx(300 * 100 * std::sin(0.01)));
  CHECK(m.t_err_percent == Approx(0.0).margin(1e-9));
  // acos of the trace near 1 rounds to ~1e-8 rad: the devkit's formula, kept.
  CHECK(m.r_err_deg_per_m == Approx(0.0).margin(1e-6));
  CHECK(m.ate_rmse_m == Approx(0.0).margin(1e-9));
  CHECK(m.ate_anchored_rmse_m == 0.0);
  CHECK(m.ate_max_m == 0.0);
  CHECK(m.mean_rpe_translation_m == Approx(0.0).margin(1e-9));
  CHECK(m.mean_rpe_rotation_deg == Approx(0.0).margin(1e-9));
}

TEST_CASE("odometry: an extra yaw of d a frame gives a rotation error of k d over k steps", "[odometry]") {
  // Ground truth: 1 m a frame along x. Estimate: every step the same 1 m forward, then yawed by
  // d more. Over k steps the estimate turns k d and the ground truth not at all, so the segment's
  // pose error turns by k d: L = 100 (k = 101) -> 0.101 rad / 100 m; L = 200 (k = 201) ->
  // 0.201 rad / 200 m.
  const double d = 0.001;
  const std::vector<Pose> gt = straight(301, 1.0);
  std::vector<Pose> est{Pose::Identity()};
  const Pose step = pose(d, 1.0, 0.0);
  while (est.size() < gt.size()) est.push_back(est.back() * step);

  const std::vector<SegmentError> s = sequence_errors(gt, est);
  REQUIRE(s.size() == 30);
  CHECK(s[0].last_frame == 101);
  CHECK(s[0].r_err_rad_per_m == Approx(0.101 / 100).epsilon(1e-9));
  CHECK(s[1].last_frame == 201);
  CHECK(s[1].r_err_rad_per_m == Approx(0.201 / 200).epsilon(1e-9));

  const OdometryMetrics m = odometry_metrics(gt, est);
  // (180 / pi) (20 * 0.00101 + 10 * 0.001005) / 30
  CHECK(m.r_err_deg_per_m == Approx(180.0 / M_PI * 0.03025 / 30).epsilon(1e-9));
  CHECK(m.per_length[0].r_err_deg_per_m == Approx(180.0 / M_PI * 0.00101).epsilon(1e-9));
  CHECK(m.per_length[1].r_err_deg_per_m == Approx(180.0 / M_PI * 0.001005).epsilon(1e-9));
  // Frame to frame: the step's own 1 m is right, only its yaw d is extra.
  CHECK(m.mean_rpe_rotation_deg == Approx(d * 180.0 / M_PI).epsilon(1e-9));
  CHECK(m.mean_rpe_translation_m == Approx(0.0).margin(1e-9));
}

TEST_CASE("odometry: a trajectory shorter than the shortest segment is too short - NaN errors", "[odometry]") {
  const std::vector<Pose> gt = straight(50, 1.0);  // 49 m
  const OdometryMetrics m = odometry_metrics(gt, gt);
  CHECK(m.frames == 50);
  CHECK(m.trajectory_length_m == 49.0);
  CHECK(m.too_short);
  CHECK(m.segments == 0);
  CHECK(std::isnan(m.t_err_percent));
  CHECK(std::isnan(m.r_err_deg_per_m));
  REQUIRE(m.per_length.size() == 8);
  for (const LengthMetrics& l : m.per_length) {
    CHECK(l.segments == 0);
    CHECK(std::isnan(l.t_err_percent));
  }
  // Trajectory errors need no segment.
  CHECK(m.ate_rmse_m == Approx(0.0).margin(1e-9));
  CHECK(m.mean_rpe_translation_m == Approx(0.0).margin(1e-12));

  // One frame: nothing to compare.
  const OdometryMetrics one = odometry_metrics(straight(1, 1.0), straight(1, 1.0));
  CHECK(one.frames == 1);
  CHECK(one.trajectory_length_m == 0.0);
  CHECK(one.too_short);
  CHECK(std::isnan(one.ate_rmse_m));
  CHECK(std::isnan(one.ate_anchored_rmse_m));
  CHECK(std::isnan(one.mean_rpe_translation_m));
  CHECK(odometry_metrics({}, {}).frames == 0);
}

TEST_CASE("odometry: ATE aligns a rotated and shifted estimate - the anchored ATE does not", "[odometry]") {
  const std::vector<Pose> gt = arc(301);
  const Pose moved = pose(M_PI / 2, 5.0, -3.0, 2.0);
  std::vector<Pose> est;
  for (const Pose& p : gt) est.push_back(moved * p);
  const OdometryMetrics m = odometry_metrics(gt, est);
  CHECK(m.ate_rmse_m == Approx(0.0).margin(1e-9));
  CHECK(m.ate_anchored_rmse_m > 1.0);
  CHECK(m.ate_max_m >= m.ate_anchored_rmse_m);
  // Segment and frame-to-frame errors are relative: a global transform does not change them.
  CHECK(m.t_err_percent == Approx(0.0).margin(1e-9));
  CHECK(m.mean_rpe_translation_m == Approx(0.0).margin(1e-9));
  CHECK(m.mean_rpe_rotation_deg == Approx(0.0).margin(1e-9));
}

TEST_CASE("odometry: bad input throws naming the counts or the pose", "[odometry]") {
  const std::vector<Pose> three = straight(3, 1.0), two = straight(2, 1.0);
  CHECK_THROWS_AS(sequence_errors(three, two), std::invalid_argument);
  CHECK_THROWS_WITH(odometry_metrics(three, two), Contains("has 3 poses") && Contains("estimate 2"));

  std::vector<Pose> bad = straight(6, 1.0);
  bad[4](1, 3) = NAN;
  CHECK_THROWS_AS(odometry_metrics(straight(6, 1.0), bad), std::invalid_argument);
  CHECK_THROWS_WITH(odometry_metrics(straight(6, 1.0), bad), Contains("estimated pose 4"));
  bad[4](1, 3) = INFINITY;
  CHECK_THROWS_WITH(odometry_metrics(bad, straight(6, 1.0)), Contains("ground-truth pose 4"));

  CHECK_THROWS_AS(sequence_errors(three, three, {100.0}, 0), std::invalid_argument);
  CHECK_THROWS_AS(sequence_errors(three, three, {0.0}), std::invalid_argument);
  CHECK_THROWS_AS(sequence_errors(three, three, {100.0}, 10, 0.0), std::invalid_argument);
}
