// The synthetic drive (see drive.hpp): town.cpp builds the town, route.cpp the route and the
// speed profile, lidar.cpp the scans; this file places the sensor and keeps the frames.
#include "drive.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "lidar.hpp"
#include "route.hpp"
#include "town.hpp"

namespace tigris {
namespace {

constexpr double kSensorHeight = 1.73;  // HDL-64E on the KITTI car: 1.73 m above the road
constexpr double kMaxSpeed = 15.0;
enum Tag : std::uint64_t { kNoiseTag = 301 };

void check_config(const DriveConfig& c) {
  std::ostringstream err;
  if (c.frames < 1 || c.frames > 20000) err << "frames must be in 1..20000 (got " << c.frames << "); ";
  if (c.rings < 1 || c.rings > 1024) err << "rings must be in 1..1024 (got " << c.rings << "); ";
  if (c.azimuth_steps < 1 || c.azimuth_steps > 100000)
    err << "azimuth_steps must be in 1..100000 (got " << c.azimuth_steps << "); ";
  if (!(c.min_range_m >= 0.0f) || !(c.max_range_m > c.min_range_m) || !std::isfinite(c.max_range_m) ||
      c.max_range_m > 1000.0f)
    err << "need 0 <= min_range_m < max_range_m <= 1000 (got " << c.min_range_m << ", " << c.max_range_m << "); ";
  if (!(c.range_noise_m >= 0.0f) || !std::isfinite(c.range_noise_m) || c.range_noise_m > 10.0f)
    err << "range_noise_m must be in [0, 10] (got " << c.range_noise_m << "); ";
  const std::string msg = err.str();
  if (!msg.empty()) throw InputError("synthetic drive: " + msg.substr(0, msg.size() - 2));
}

// The sensor on the car at (x, y) heading (hx, hy): its up is the ground's normal, forward the
// heading lifted onto the ground's tangent plane.
synth::Pose34 sensor_pose(const synth::Ground& g, double x, double y, double hx, double hy) {
  const double gx = g.dx(x, y), gy = g.dy(x, y);
  const auto unit = [](double& a, double& b, double& c) {
    const double n = std::sqrt((a * a + b * b) + c * c);
    a /= n;
    b /= n;
    c /= n;
  };
  double nx = -gx, ny = -gy, nz = 1.0;
  unit(nx, ny, nz);
  double fx = hx, fy = hy, fz = gx * hx + gy * hy;
  unit(fx, fy, fz);
  double lx = ny * fz - nz * fy, ly = nz * fx - nx * fz, lz = nx * fy - ny * fx;  // left = n x f
  unit(lx, ly, lz);
  fx = ly * nz - lz * ny;  // forward = left x n: exactly orthogonal to both
  fy = lz * nx - lx * nz;
  fz = lx * ny - ly * nx;
  const double z = g.height(x, y);
  return synth::Pose34{fx, lx, nx, x + kSensorHeight * nx,  //
                       fy, ly, ny, y + kSensorHeight * ny,  //
                       fz, lz, nz, z + kSensorHeight * nz};
}

// inv(a) * b for rigid 3x4 transforms.
synth::Pose34 relative(const synth::Pose34& a, const synth::Pose34& b) {
  synth::Pose34 r{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      double v = 0.0;
      for (int k = 0; k < 3; ++k) v += a[4 * k + i] * (j < 3 ? b[4 * k + j] : b[4 * k + 3] - a[4 * k + 3]);
      r[4 * i + j] = v;
    }
  }
  return r;
}

}  // namespace

struct SyntheticDrive::Impl {
  synth::Town town;
  std::vector<synth::Pose34> world;  // sensor frame -> town frame, per frame
};

SyntheticDrive::SyntheticDrive(const DriveConfig& config) : config_(config), impl_(std::make_unique<Impl>()) {
  check_config(config);
  const synth::StreetGrid grid(config.seed);
  const double need = config.frames * 0.1 * kMaxSpeed + 100.0;
  const synth::Route route = synth::plan_route(config.seed, grid, need);
  const std::vector<synth::ProfileSample> profile = synth::speed_profile(route, config.frames);
  const synth::Ground ground = synth::make_ground(config.seed);

  double x = 0, y = 0, hx = 1, hy = 0;
  for (std::size_t i = 0; i < profile.size(); ++i) {
    route.at(profile[i].s, x, y, hx, hy);
    impl_->world.push_back(sensor_pose(ground, x, y, hx, hy));
    DriveFrame f;
    f.time_s = 0.1 * static_cast<double>(i);
    f.speed_m_per_s = profile[i].speed;
    f.distance_m = profile[i].s;
    f.pose = i == 0 ? synth::Pose34{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}
                    : relative(impl_->world.front(), impl_->world.back());
    frames_.push_back(f);
  }
  // The town the sensor can see: every block within reach of the path driven (sampled every 5 m).
  std::vector<double> path;
  const double driven = profile.back().s;
  for (double s = 0.0;; s += 5.0) {
    route.at(std::min(s, driven), x, y, hx, hy);
    path.push_back(x);
    path.push_back(y);
    summary_.max_grade =
        std::max(summary_.max_grade, std::sqrt(ground.dx(x, y) * ground.dx(x, y) + ground.dy(x, y) * ground.dy(x, y)));
    if (s >= driven) break;
  }
  impl_->town = synth::make_town(config.seed, grid, path, config.max_range_m + 20.0);
  summary_.route_length_m = driven;
  for (const synth::SpeedLimit& l : route.limits) {  // what the car passed (a new cruise: a crossing)
    if (l.s_from > driven) continue;
    summary_.crossings += l.cruise && l.s_from > 0.0;
    summary_.turns += !l.cruise && !l.stop;
    summary_.stops += l.stop;
  }
  summary_.buildings_and_cars = impl_->town.boxes.size();
  summary_.poles_and_trunks = impl_->town.cylinders.size();
  summary_.tree_crowns = impl_->town.spheres.size();
}

SyntheticDrive::~SyntheticDrive() = default;
SyntheticDrive::SyntheticDrive(SyntheticDrive&&) noexcept = default;

PointCloud SyntheticDrive::scan(int frame) const {
  if (frame < 0 || frame >= static_cast<int>(frames_.size()))
    throw InputError("synthetic drive: no frame " + std::to_string(frame) + " (the drive has " +
                     std::to_string(frames_.size()) + ")");
  synth::LidarConfig lc;
  lc.rings = config_.rings;
  lc.azimuth_steps = config_.azimuth_steps;
  lc.min_range_m = config_.min_range_m;
  lc.max_range_m = config_.max_range_m;
  lc.range_noise_m = config_.range_noise_m;
  det::Rng noise(config_.seed, synth::stream_id(kNoiseTag, frame, 0));
  return synth::lidar_scan(impl_->town, impl_->world[static_cast<std::size_t>(frame)], lc, noise);
}

}  // namespace tigris
