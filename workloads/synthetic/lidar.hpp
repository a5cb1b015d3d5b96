// An HDL-64E-like scan of the synthetic town from any 6-DoF sensor pose (drive.hpp). Internal
// to workloads/synthetic.
#pragma once

#include <array>

#include "det_math.hpp"
#include "sw_ref/cloud.hpp"
#include "town.hpp"

namespace tigris::synth {

struct LidarConfig {
  int rings = 64;
  int azimuth_steps = 1800;
  double min_range_m = 2.5, max_range_m = 80.0, range_noise_m = 0.02;
};

// Row-major 3x4 [R | t]: sensor frame to town frame.
using Pose34 = std::array<double, 12>;

// One revolution, all rays at once (no motion during the sweep), as points of the sensor frame
// (x forward, y left, z up) in ring-major order like the pair of synthetic.hpp: ring 0 the
// highest laser, azimuth j at j * 360 / azimuth_steps degrees counter-clockwise from +x. Each ray
// draws one normal variate from `noise`, hit or not; rays without a surface within the ranges
// are dropped.
PointCloud lidar_scan(const Town& town, const Pose34& pose, const LidarConfig& config, det::Rng& noise);

}  // namespace tigris::synth
