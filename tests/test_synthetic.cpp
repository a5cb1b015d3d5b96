// The synthetic LiDAR pair (workloads/synthetic.hpp): size, determinism, geometry, ground truth.
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <vector>

#include "test_util.hpp"
#include "workloads/frame_pair.hpp"
#include "workloads/synthetic.hpp"

using tigris::test::bits;
using tigris::test::same_bits;

namespace {

using tigris::Point3;
using tigris::PointCloud;
using tigris::SyntheticConfig;
using tigris::SyntheticPair;
using tigris::Transform;

// FNV-1a over the bit patterns of every coordinate: a fingerprint of a cloud.
std::uint64_t fingerprint(const PointCloud& cloud) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const Point3& p : cloud)
    for (float f : {p.x, p.y, p.z}) {
      std::uint32_t u = bits(f);
      for (int i = 0; i < 4; ++i, u >>= 8) {
        h ^= u & 0xFFu;
        h *= 0x100000001b3ull;
      }
    }
  return h;
}

// p0 = T * p1, in float32.
Point3 apply(const Transform& t, const Point3& p) {
  return Point3{((t[0] * p.x + t[1] * p.y) + t[2] * p.z) + t[3], ((t[4] * p.x + t[5] * p.y) + t[6] * p.z) + t[7],
                ((t[8] * p.x + t[9] * p.y) + t[10] * p.z) + t[11]};
}

// Distance from each query to its nearest reference point, by brute force.
std::vector<float> nn_distances(const PointCloud& queries, const PointCloud& ref) {
  std::vector<float> d;
  d.reserve(queries.size());
  for (const Point3& q : queries) {
    float best = tigris::kInfinity;
    for (const Point3& r : ref) best = std::min(best, tigris::dist2(q, r));
    d.push_back(std::sqrt(best));
  }
  std::sort(d.begin(), d.end());
  return d;
}

double range(const Point3& p) {
  const double x = p.x, y = p.y, z = p.z;
  return std::sqrt(x * x + y * y + z * z);
}

double elevation_deg(const Point3& p) {
  const double x = p.x, y = p.y, z = p.z;
  return std::atan2(z, std::sqrt(x * x + y * y)) * (180.0 / 3.14159265358979323846);
}

const SyntheticPair& default_pair() {
  static const SyntheticPair pair = tigris::make_synthetic_pair();
  return pair;
}

}  // namespace

TEST_CASE("synthetic: the default scans have an HDL-64E-like point count", "[synthetic]") {
  const auto t0 = std::chrono::steady_clock::now();
  const SyntheticPair pair = tigris::make_synthetic_pair();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "synthetic pair (seed 1): frame0 " << pair.frame0.size() << " points, frame1 " << pair.frame1.size()
            << " points, generated in " << seconds << " s\n";
  CHECK(pair.frame0.size() >= 100000);
  CHECK(pair.frame0.size() <= 130000);
  CHECK(pair.frame1.size() >= 100000);
  CHECK(pair.frame1.size() <= 130000);
  CHECK(pair.frame0.size() <= 64u * 1800u);  // at most one return per ray
  CHECK(seconds < 5.0);                      // about 0.02 s in Release; generous for sanitizer and Debug builds
}

TEST_CASE("synthetic: other seeds stay in the point-count range", "[synthetic]") {
  for (std::uint64_t seed : {2ull, 3ull, 7ull, 1234567ull}) {
    SyntheticConfig config;
    config.seed = seed;
    const SyntheticPair pair = tigris::make_synthetic_pair(config);
    INFO("seed " << seed << ": " << pair.frame0.size() << " / " << pair.frame1.size());
    CHECK(pair.frame0.size() >= 100000);
    CHECK(pair.frame0.size() <= 130000);
    CHECK(pair.frame1.size() >= 100000);
    CHECK(pair.frame1.size() <= 130000);
  }
}

TEST_CASE("synthetic: same seed gives the same bits, another seed another scene", "[synthetic]") {
  const SyntheticPair& a = default_pair();
  const SyntheticPair b = tigris::make_synthetic_pair();
  CHECK(same_bits(a.frame0, b.frame0));
  CHECK(same_bits(a.frame1, b.frame1));
  CHECK(a.frame1_to_frame0 == b.frame1_to_frame0);

  SyntheticConfig other;
  other.seed = 2;
  const SyntheticPair c = tigris::make_synthetic_pair(other);
  CHECK_FALSE(same_bits(a.frame0, c.frame0));
  CHECK_FALSE(same_bits(a.frame1, c.frame1));
  // The two scans of one pair are different scans (pose and noise stream).
  CHECK_FALSE(same_bits(a.frame0, a.frame1));
}

TEST_CASE("synthetic: the seed-1 pair has a fixed fingerprint on every platform", "[synthetic]") {
  // The generator uses no std::*_distribution and no libm function whose last bit varies
  // between C libraries, so these values hold for every conforming C++17 toolchain (built with
  // -ffp-contract=off). They change only when the generator itself is changed on purpose:
  // then update them (and say so in the change log, since every synthetic result moves).
  const SyntheticPair& pair = default_pair();
  INFO("frame0 " << pair.frame0.size() << " points, fingerprint 0x" << std::hex << fingerprint(pair.frame0)
                 << "; frame1 " << std::dec << pair.frame1.size() << " points, fingerprint 0x" << std::hex
                 << fingerprint(pair.frame1));
  CHECK(pair.frame0.size() == 115200u);
  CHECK(pair.frame1.size() == 115110u);
  CHECK(fingerprint(pair.frame0) == 0xd25e067ac3ad6b6eull);
  CHECK(fingerprint(pair.frame1) == 0x5508015f82bf4153ull);
}

TEST_CASE("synthetic: points are finite, within the range limits and above the ground", "[synthetic]") {
  const SyntheticConfig config;
  const SyntheticPair& pair = default_pair();
  for (const PointCloud* cloud : {&pair.frame0, &pair.frame1}) {
    REQUIRE_NOTHROW(tigris::validate_cloud(*cloud, "synthetic"));
    double min_r = 1e9, max_r = 0.0;
    float min_z = 1e9f, max_z = -1e9f;
    for (const Point3& p : *cloud) {
      min_r = std::min(min_r, range(p));
      max_r = std::max(max_r, range(p));
      min_z = std::min(min_z, p.z);
      max_z = std::max(max_z, p.z);
    }
    CHECK(min_r >= config.min_range_m - 1e-4);
    CHECK(max_r <= config.max_range_m + 1e-4);
    CHECK(min_z >= -1.73f - 0.15f);  // ground at -1.73 m in the sensor frame, plus noise
    CHECK(max_z <= 25.0f);
  }
}

TEST_CASE("synthetic: point order is ring-major, highest ring first, azimuth counter-clockwise", "[synthetic]") {
  const PointCloud& cloud = default_pair().frame0;
  CHECK(elevation_deg(cloud.front()) == Approx(2.0).margin(1e-3));
  CHECK(elevation_deg(cloud.back()) == Approx(-24.8).margin(1e-3));
  // The range noise moves a point along its ray, so the elevation is that of its ring.
  std::size_t ring_changes = 0, going_up = 0;
  for (std::size_t i = 1; i < cloud.size(); ++i) {
    const double e0 = elevation_deg(cloud[i - 1]), e1 = elevation_deg(cloud[i]);
    if (e1 > e0 + 1e-3) ++going_up;
    if (e1 < e0 - 0.1) ++ring_changes;
  }
  CHECK(going_up == 0u);
  CHECK(ring_changes == 63u);
  // The first ring starts at azimuth 0 (+x) and turns towards +y.
  CHECK(std::atan2(cloud[0].y, cloud[0].x) == Approx(0.0).margin(1e-4));
  CHECK(std::atan2(cloud[1].y, cloud[1].x) > 0.0);
}

TEST_CASE("synthetic: without noise the ground returns lie on the ground plane", "[synthetic]") {
  SyntheticConfig config;
  config.range_noise_m = 0.0f;
  const SyntheticPair pair = tigris::make_synthetic_pair(config);
  std::size_t on_ground = 0, below_ground = 0;
  for (const Point3& p : pair.frame0) {
    if (std::fabs(p.z + 1.73f) < 1e-4f) ++on_ground;
    if (p.z < -1.73f - 1e-4f) ++below_ground;
  }
  CHECK(on_ground > pair.frame0.size() / 3);
  CHECK(below_ground == 0u);
}

TEST_CASE("synthetic: the ground-truth transform maps frame 1 onto frame 0", "[synthetic]") {
  const SyntheticConfig config;
  const SyntheticPair& pair = default_pair();
  const Transform& t = pair.frame1_to_frame0;
  // A rigid motion: yaw about +z and a forward translation, bottom row 0 0 0 1.
  const double yaw = config.yaw_deg * (3.14159265358979323846 / 180.0);
  CHECK(t[0] == Approx(std::cos(yaw)).margin(1e-6));
  CHECK(t[1] == Approx(-std::sin(yaw)).margin(1e-6));
  CHECK(t[4] == Approx(std::sin(yaw)).margin(1e-6));
  CHECK(t[5] == Approx(std::cos(yaw)).margin(1e-6));
  CHECK(t[3] == config.forward_m);
  CHECK(t[7] == 0.0f);
  CHECK(t[11] == 0.0f);
  CHECK(t[10] == 1.0f);
  CHECK(t[12] == 0.0f);
  CHECK(t[13] == 0.0f);
  CHECK(t[14] == 0.0f);
  CHECK(t[15] == 1.0f);

  // Frame-1 points off the ground, with and without the transform, against all of frame 0. (The
  // ground is left out: both sensors are 1.73 m above a flat ground, so a ground return has the
  // same sensor coordinates in both scans whatever the motion, and would hide a wrong pose.)
  PointCloud aligned, unaligned;
  for (std::size_t i = 0; i < pair.frame1.size(); i += 37) {
    const Point3& p = pair.frame1[i];
    if (p.z < -1.5f) continue;
    unaligned.push_back(p);
    aligned.push_back(apply(t, p));
  }
  REQUIRE(aligned.size() > 500);
  const std::vector<float> da = nn_distances(aligned, pair.frame0);
  const std::vector<float> du = nn_distances(unaligned, pair.frame0);
  const float median_a = da[da.size() / 2], median_u = du[du.size() / 2];
  const float p90_a = da[da.size() * 9 / 10], p90_u = du[du.size() * 9 / 10];
  INFO("NN distance, aligned: median " << median_a << " p90 " << p90_a << "; unaligned: median " << median_u << " p90 "
                                       << p90_u);
  CHECK(median_a < 0.1f);  // about 0.03 m: sampling density and 2 cm range noise
  CHECK(p90_a < 0.2f);
  CHECK(median_u > 2.0f * median_a);
  CHECK(p90_u > 0.5f);
}

TEST_CASE("synthetic: other scan settings and bad settings", "[synthetic]") {
  SyntheticConfig small;
  small.rings = 16;
  small.azimuth_steps = 360;
  const SyntheticPair pair = tigris::make_synthetic_pair(small);
  CHECK(pair.frame0.size() > 16u * 360u / 2);
  CHECK(pair.frame0.size() <= 16u * 360u);
  CHECK_NOTHROW(tigris::validate_cloud(pair.frame1, "small"));

  SyntheticConfig bad;
  bad.rings = 0;
  CHECK_THROWS_AS(tigris::make_synthetic_pair(bad), tigris::InputError);
  bad = SyntheticConfig{};
  bad.max_range_m = 1.0f;  // below min_range_m
  CHECK_THROWS_AS(tigris::make_synthetic_pair(bad), tigris::InputError);
  bad = SyntheticConfig{};
  bad.range_noise_m = -0.1f;
  CHECK_THROWS_AS(tigris::make_synthetic_pair(bad), tigris::InputError);
  bad = SyntheticConfig{};
  bad.yaw_deg = std::nanf("");
  CHECK_THROWS_AS(tigris::make_synthetic_pair(bad), tigris::InputError);
}

TEST_CASE("register's frame pair: the built-in pair with its known pose, or files naming the one at fault",
          "[frame_pair]") {
  using tigris::FramePair, tigris::FramePairSpec, tigris::load_frame_pair;
  const FramePair f = load_frame_pair({});
  CHECK(f.source_name == "synthetic:frame1 (seed 1)");
  CHECK(f.target_name == "synthetic:frame0 (seed 1)");
  CHECK(f.source.size() > 100000);
  REQUIRE(f.truth);
  CHECK((*f.truth)(3, 3) == 1.0);
  CHECK(f.truth_warning.empty());
  FramePairSpec spec;
  spec.source = "/nonexistent/a.bin";
  spec.target = "/nonexistent/b.bin";
  try {
    load_frame_pair(spec);
    FAIL("no error");
  } catch (const std::exception& e) {
    CHECK(std::string(e.what()).find("/nonexistent/a.bin") != std::string::npos);
  }
}
