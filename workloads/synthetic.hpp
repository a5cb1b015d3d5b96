// Deterministic, seedable synthetic LiDAR: an HDL-64E-like scan of a street scene and a second
// scan of the same scene from a known pose, the default workload of every command and test.
#pragma once

#include <array>
#include <cstdint>

#include "sw_ref/cloud.hpp"

namespace tigris {

struct SyntheticConfig {
  std::uint64_t seed = 1;
  int rings = 64;               // laser rings (HDL-64E: 64)
  int azimuth_steps = 1800;     // firings per revolution (0.2 degree)
  float max_range_m = 80.0f;    // returns beyond this are dropped
  float min_range_m = 2.5f;     // the ego car hides closer returns
  float range_noise_m = 0.02f;  // 1-sigma Gaussian range noise
  float forward_m = 1.0f;       // second scan: sensor moved this far along +x ...
  float yaw_deg = 1.0f;         // ... and turned this much about +z
};

// Row-major 4x4 rigid transform.
using Transform = std::array<float, 16>;

struct SyntheticPair {
  PointCloud frame0;  // scan from the origin: the cloud the tree is built on
  PointCloud frame1;  // scan from the second pose: the queries
  // Ground truth: maps frame-1 sensor coordinates to frame-0 coordinates (p0 = T * p1).
  Transform frame1_to_frame0{};
};

// Throws InputError("synthetic scene: ...") for impossible settings (no rings, max range
// below min range, negative noise, non-finite pose).
SyntheticPair make_synthetic_pair(const SyntheticConfig& config = {});

}  // namespace tigris
