// The synthetic drive (docs/registration.md): a seeded town (a grid of streets with
// turns and intersections on gently sloped ground; blocks of buildings with setbacks and gaps,
// now and then a park; parked cars, poles and trees at the curbs), a car driving through it at
// 0-15 m/s (accelerating, braking, turning, stopping at crossings) sampled at 10 Hz, and an
// HDL-64E-like scan with range noise from each frame's exact 6-DoF sensor pose (the sensor 1.73 m
// above the road along the ground's normal, so it pitches and rolls on the slopes).
//
// Deterministic across machines like the pair of synthetic.hpp (det_math.hpp): the same seed
// gives the same bits everywhere. A drive is a prefix of any longer drive of the same seed: the
// street grid, each block's content and the route are fixed by the seed, not by the length.
// Scans are instantaneous (no motion during a sweep) and have no reflectance.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sw_ref/cloud.hpp"

namespace tigris {

struct DriveConfig {
  std::uint64_t seed = 1;
  int frames = 100;  // at 10 Hz
  int rings = 64;    // the scanner, as in SyntheticConfig
  int azimuth_steps = 1800;
  float max_range_m = 80.0f;
  float min_range_m = 2.5f;
  float range_noise_m = 0.02f;
};

struct DriveFrame {
  double time_s = 0;
  double speed_m_per_s = 0;
  double distance_m = 0;  // along the route from frame 0
  // Row-major 3x4 [R | t]: this frame's sensor frame in frame 0's sensor frame (KITTI's
  // convention for poses, in the Velodyne frame).
  std::array<double, 12> pose{};
};

struct DriveSummary {
  double route_length_m = 0;                // of the frames driven
  int crossings = 0, turns = 0, stops = 0;  // on the way driven, frame 0 to the last frame
  std::size_t buildings_and_cars = 0, poles_and_trunks = 0, tree_crowns = 0;
  double max_grade = 0;  // steepest ground slope under the car's path
};

class SyntheticDrive {
 public:
  // Plans the route and builds the town (fast); scans are cast on demand. Throws
  // InputError("synthetic drive: ...") for impossible settings.
  explicit SyntheticDrive(const DriveConfig& config);
  ~SyntheticDrive();
  SyntheticDrive(SyntheticDrive&&) noexcept;

  const DriveConfig& config() const { return config_; }
  const std::vector<DriveFrame>& frames() const { return frames_; }
  const DriveSummary& summary() const { return summary_; }
  // Frame i's scan, in its sensor frame (x forward, y left, z up), ring-major.
  PointCloud scan(int frame) const;

 private:
  struct Impl;
  DriveConfig config_;
  std::vector<DriveFrame> frames_;
  DriveSummary summary_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tigris
