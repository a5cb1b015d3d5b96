// Synthetic HDL-64E-like street scans (see synthetic.hpp).
//
// Determinism: the same SyntheticConfig gives the same bits on every conforming platform
// (synthetic/det_math.hpp says how); everything is computed in double and rounded to float32 once,
// at the end.
//
// Frames. The scene is built in a ground frame: ground plane z = 0, street along +x, the frame-0
// sensor at (0, 0, 1.73) looking along +x. The public frame-0 ("world") coordinates are the
// frame-0 sensor frame, i.e. the ground frame shifted down by the sensor height (the ground is at
// z = -1.73). The frame-1 sensor sits at (forward_m, 0, 1.73), yawed by yaw_deg about +z.
//
// Point order (both scans): ring-major, like the KITTI .bin files. Ring 0 is the highest laser
// (+2.0 degrees), ring 63 the lowest (-24.8 degrees); within a ring, azimuth index
// j = 0 .. azimuth_steps-1 at azimuth j * 360 / azimuth_steps degrees counter-clockwise from the
// sensor's +x axis. Rays without a return (no surface within [min_range_m, max_range_m]) are
// dropped, so a point's index is its rank among the returning rays in that order.
#include "synthetic.hpp"
#include "workloads/synthetic/det_math.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

namespace tigris {
namespace {

using namespace det;

constexpr double kSensorHeight = 1.73;  // HDL-64E on the KITTI car: 1.73 m above the road
constexpr double kInf = std::numeric_limits<double>::infinity();

enum Stream : std::uint64_t { kSceneStream = 1, kNoiseFrame0 = 2, kNoiseFrame1 = 3 };

// ---------------------------------------------------------------------------------------------
// Scene: vertical prisms (axis-aligned boxes, capped vertical cylinders) and spheres on a flat
// ground plane z = 0 (ground frame).

struct Box {
  double x0, x1, y0, y1, z0, z1;
};
struct Cylinder {
  double cx, cy, r, z0, z1;
};
struct Sphere {
  double cx, cy, cz, r;
};

struct Scene {
  std::vector<Box> boxes;
  std::vector<Cylinder> cylinders;
  std::vector<Sphere> spheres;
};

// One side of the street (side = +1: +y, side = -1: -y); `base` is the distance of the
// building line from the street axis.
void add_building_row(Scene& scene, Rng& rng, double xa, double xb, int side, double base, double min_depth,
                      double max_depth, double min_h, double max_h, double max_setback, bool gaps) {
  double x = xa;
  while (x < xb - 1.0) {
    double end = std::min(x + rng.uniform(8.0, 25.0), xb);
    if (xb - end < 4.0) end = xb;  // no sliver buildings at the end of a row
    const double setback = rng.chance(0.5) ? 0.0 : rng.uniform(0.0, max_setback);
    const double depth = rng.uniform(min_depth, max_depth);
    const double height = rng.uniform(min_h, max_h);
    const double near = base + setback;
    const double far = near + depth;
    Box b{x, end, 0.0, 0.0, 0.0, height};
    b.y0 = side > 0 ? near : -far;
    b.y1 = side > 0 ? far : -near;
    scene.boxes.push_back(b);
    x = end;
    if (gaps && !rng.chance(0.35)) x += rng.uniform(1.5, 6.0);
  }
}

// A car-like box standing on the ground, centred at (cx, cy).
void add_car(Scene& scene, double cx, double cy, double length, double width, double height) {
  scene.boxes.push_back(Box{cx - 0.5 * length, cx + 0.5 * length, cy - 0.5 * width, cy + 0.5 * width, 0.0, height});
}

// Buildings closing the street at both ends (x_front ahead, x_back behind), split in a few blocks.
void add_end_buildings(Scene& scene, Rng& rng, double x_front, double x_back) {
  for (int end = 0; end < 2; ++end) {
    const double xn = end == 0 ? x_front : x_back;  // near face
    double y = -60.0;
    while (y < 60.0) {
      double y_end = std::min(y + rng.uniform(15.0, 40.0), 60.0);
      if (60.0 - y_end < 8.0) y_end = 60.0;
      const double setback = rng.chance(0.5) ? 0.0 : rng.uniform(0.0, 3.0);
      const double depth = rng.uniform(10.0, 20.0);
      const double height = rng.uniform(10.0, 25.0);
      Box b{0.0, 0.0, y, y_end, 0.0, height};
      if (end == 0) {
        b.x0 = xn + setback;
        b.x1 = xn + setback + depth;
      } else {
        b.x0 = xn - setback - depth;
        b.x1 = xn - setback;
      }
      scene.boxes.push_back(b);
      y = y_end;
    }
  }
}

// One side of the street (side +1: +y) with its curb at |y| = curb: parked cars, poles and lamp
// posts, street trees; none across the cross street [cross0, cross1].
void add_street_side(Scene& scene, Rng& rng, int side, double curb, double x_back, double x_front, double cross0,
                     double cross1) {
  // Parked cars along the curb (no parking across the cross street).
  double x = x_back + 4.0;
  while (x < x_front - 8.0) {
    if (x > cross0 - 8.0 && x < cross1 + 2.0) {
      x = cross1 + 2.0;
      continue;
    }
    if (rng.chance(0.65)) {
      const bool van = rng.chance(0.12);
      const double length = van ? rng.uniform(5.0, 6.0) : rng.uniform(3.9, 4.6);
      const double width = van ? rng.uniform(1.9, 2.0) : rng.uniform(1.7, 1.9);
      const double height = van ? rng.uniform(2.0, 2.4) : rng.uniform(1.4, 1.6);
      add_car(scene, x + 0.5 * length, side * (curb - 0.25 - 0.5 * width), length, width, height);
      x += length + rng.uniform(0.8, 3.0);
    } else {
      x += rng.uniform(2.0, 6.0);
    }
  }
  // Poles and lamp posts at the curb.
  x = x_back + rng.uniform(2.0, 10.0);
  while (x < x_front - 2.0) {
    if (x < cross0 || x > cross1) {
      const double py = side * (curb + rng.uniform(0.4, 0.7));
      const double radius = rng.uniform(0.08, 0.15);
      const double height = rng.uniform(5.0, 9.0);
      scene.cylinders.push_back(Cylinder{x, py, radius, 0.0, height});
    }
    x += rng.uniform(15.0, 25.0);
  }
  // Street trees on the sidewalk: trunk (cylinder) and crown (sphere).
  x = x_back + rng.uniform(3.0, 12.0);
  while (x < x_front - 3.0) {
    if ((x < cross0 - 2.0 || x > cross1 + 2.0) && rng.chance(0.5)) {
      const double ty = side * (curb + rng.uniform(1.2, 1.8));
      const double trunk_h = rng.uniform(2.2, 3.5);
      const double crown_r = rng.uniform(1.2, 2.2);
      const double trunk_r = rng.uniform(0.12, 0.25);
      scene.cylinders.push_back(Cylinder{x, ty, trunk_r, 0.0, trunk_h});
      scene.spheres.push_back(Sphere{x, ty, trunk_h + 0.7 * crown_r, crown_r});
    }
    x += rng.uniform(8.0, 20.0);
  }
}

Scene make_scene(std::uint64_t seed) {
  Rng rng(seed, kSceneStream);
  Scene scene;

  const double curb[2] = {rng.uniform(5.5, 7.0), rng.uniform(5.5, 7.0)};      // +y, -y side
  const double sidewalk[2] = {rng.uniform(2.5, 4.0), rng.uniform(2.5, 4.0)};  // curb to facade
  const double x_front = rng.uniform(55.0, 68.0);                             // closing facade ahead
  const double x_back = -rng.uniform(45.0, 60.0);                             // closing facade behind
  // An open cross street [cross0, cross1], from around the sensor up to 30 m ahead. When the
  // sensor is near the intersection, the upper rings looking down it see nothing within
  // max_range (no return) and the lower ones see far ground.
  const double cross0 = rng.uniform(-6.0, 30.0);
  const double cross1 = cross0 + rng.uniform(10.0, 14.0);

  for (int k = 0; k < 2; ++k) {
    const int side = k == 0 ? 1 : -1;
    const double facade = curb[k] + sidewalk[k];
    // Street-front buildings (setbacks, gaps), interrupted by the cross street.
    add_building_row(scene, rng, x_back, cross0, side, facade, 10.0, 20.0, 8.0, 20.0, 3.0, true);
    add_building_row(scene, rng, cross1, x_front, side, facade, 10.0, 20.0, 8.0, 20.0, 3.0, true);
    // Back row: seen through the gaps between the front buildings.
    const double back = facade + rng.uniform(24.0, 28.0);
    add_building_row(scene, rng, x_back, cross0, side, back, 8.0, 12.0, 10.0, 24.0, 0.0, false);
    add_building_row(scene, rng, cross1, x_front, side, back, 8.0, 12.0, 10.0, 24.0, 0.0, false);
  }
  add_end_buildings(scene, rng, x_front, x_back);
  for (int k = 0; k < 2; ++k) add_street_side(scene, rng, k == 0 ? 1 : -1, curb[k], x_back, x_front, cross0, cross1);
  // One or two cars in the oncoming lane (+y side), ahead of or behind the sensor.
  const int traffic = rng.chance(0.5) ? 1 : 2;
  for (int i = 0; i < traffic; ++i) {
    const double length = rng.uniform(4.0, 4.7);
    const double cx = rng.chance(0.6) ? rng.uniform(10.0, 16.0) : -rng.uniform(10.0, 40.0);
    // One draw per statement: the order of evaluation of function arguments is unspecified.
    const double height = rng.uniform(1.4, 1.6);
    const double width = rng.uniform(1.7, 1.9);
    add_car(scene, cx, curb[0] - 3.65, length, width, height);
  }
  return scene;
}

// ---------------------------------------------------------------------------------------------
// Ray casting. All rays of one azimuth share a horizontal direction u, so each primitive is
// first intersected in 2D (horizontal distance s along u); only the primitives crossed by that
// 2D ray are tested per ring. A ray of elevation e reaches horizontal distance s at height
// h + s tan(e) and range s / cos(e).

struct Candidate {
  double s_in;   // horizontal distance where the 2D ray enters the footprint (>= 0)
  double s_out;  // ... and leaves it
  int kind;      // 0: prism (box or cylinder) with z range [z0, z1]; 1: sphere
  int index;     // prism: index into prism_z; sphere: index into scene.spheres
};

struct Ring {
  double sin_e, cos_e, tan_e;
};

struct Pose {
  double x, y, cos_yaw, sin_yaw;  // sensor position (ground frame) and heading
};

// The primitives a horizontal ray from (ox, oy) along (ux, uy) crosses, as intervals of
// horizontal distance: boxes by a 2D slab test, cylinders and spheres by their footprint circle.
void crossed_2d(const Scene& scene, double ox, double oy, double ux, double uy, std::vector<Candidate>& cands) {
  const int n_boxes = static_cast<int>(scene.boxes.size());
  cands.clear();
  // Boxes: 2D slab test.
  for (int i = 0; i < n_boxes; ++i) {
    const Box& b = scene.boxes[static_cast<std::size_t>(i)];
    double lo = 0.0, hi = kInf;
    bool miss = false;
    const double o[2] = {ox, oy}, u[2] = {ux, uy};
    const double bmin[2] = {b.x0, b.y0}, bmax[2] = {b.x1, b.y1};
    for (int a = 0; a < 2 && !miss; ++a) {
      if (std::fabs(u[a]) < 1e-15) {
        if (o[a] < bmin[a] || o[a] > bmax[a]) miss = true;
        continue;
      }
      double t0 = (bmin[a] - o[a]) / u[a];
      double t1 = (bmax[a] - o[a]) / u[a];
      if (t0 > t1) std::swap(t0, t1);
      lo = std::max(lo, t0);
      hi = std::min(hi, t1);
      if (lo > hi) miss = true;
    }
    if (!miss) cands.push_back(Candidate{lo, hi, 0, i});
  }
  // Cylinders and spheres: their footprint circle (kind 0: a prism after the boxes; 1: a sphere).
  const auto circle = [&](double cx, double cy, double r, int kind, int index) {
    const double dx = ox - cx, dy = oy - cy;
    const double b = dx * ux + dy * uy;
    const double disc = b * b - ((dx * dx + dy * dy) - r * r);
    if (disc < 0.0) return;
    const double sq = std::sqrt(disc);
    const double s1 = -b + sq;
    if (s1 < 0.0) return;
    cands.push_back(Candidate{std::max(-b - sq, 0.0), s1, kind, index});
  };
  for (std::size_t i = 0; i < scene.cylinders.size(); ++i)
    circle(scene.cylinders[i].cx, scene.cylinders[i].cy, scene.cylinders[i].r, 0, n_boxes + static_cast<int>(i));
  for (std::size_t i = 0; i < scene.spheres.size(); ++i)
    circle(scene.spheres[i].cx, scene.spheres[i].cy, scene.spheres[i].r, 1, static_cast<int>(i));
}

// The horizontal distance of the first surface a ring's ray hits among the sorted candidates
// (prisms' z ranges in prism_z0/z1), the ground included; beyond max_range when none.
double first_hit(const Scene& scene, const Ring& ring, const std::vector<Candidate>& cands,
                 const std::vector<double>& prism_z0, const std::vector<double>& prism_z1, double ox, double oy,
                 double ux, double uy, double max_range) {
  const double h = kSensorHeight;
  // Anything beyond max_range is no return, so there is no need to look further.
  double best = (max_range + 1.0) * ring.cos_e;
  if (ring.tan_e < 0.0) best = std::min(best, h / -ring.tan_e);  // ground plane z = 0
  for (const Candidate& c : cands) {
    if (c.s_in >= best) break;
    if (c.kind == 0) {
      // Vertical prism: intersect the footprint interval with the z slab.
      const double z0 = prism_z0[static_cast<std::size_t>(c.index)];
      const double z1 = prism_z1[static_cast<std::size_t>(c.index)];
      double lo = c.s_in, hi = c.s_out;
      if (ring.tan_e > 0.0) {
        lo = std::max(lo, (z0 - h) / ring.tan_e);
        hi = std::min(hi, (z1 - h) / ring.tan_e);
      } else if (ring.tan_e < 0.0) {
        lo = std::max(lo, (z1 - h) / ring.tan_e);
        hi = std::min(hi, (z0 - h) / ring.tan_e);
      } else if (h < z0 || h > z1) {
        continue;
      }
      if (lo <= hi && lo < best) best = lo;
    } else {
      // Sphere: 3D quadratic in the range t; direction d = (cos_e u, sin_e).
      const Sphere& sp = scene.spheres[static_cast<std::size_t>(c.index)];
      const double dx = ox - sp.cx, dy = oy - sp.cy, dz = h - sp.cz;
      const double b = (dx * (ring.cos_e * ux) + dy * (ring.cos_e * uy)) + dz * ring.sin_e;
      const double disc = b * b - (((dx * dx + dy * dy) + dz * dz) - sp.r * sp.r);
      if (disc < 0.0) continue;
      const double sq = std::sqrt(disc);
      double t = -b - sq;
      if (t < 0.0) t = -b + sq;
      if (t < 0.0) continue;
      const double s = t * ring.cos_e;
      if (s < best) best = s;
    }
  }
  return best;
}

// Casts one full revolution from `pose`; out[ring * azimuth_steps + j] gets the range of the
// first surface hit, or a negative value when there is none within max_range.
void cast_scan(const Scene& scene, const Pose& pose, const std::vector<Ring>& rings, const std::vector<double>& az_cos,
               const std::vector<double>& az_sin, double max_range, std::vector<double>& out) {
  const std::size_t n_rings = rings.size();
  const std::size_t n_az = az_cos.size();
  out.assign(n_rings * n_az, -1.0);

  // z ranges of the prisms: boxes first, then cylinders.
  std::vector<double> prism_z0, prism_z1;
  for (const Box& b : scene.boxes) {
    prism_z0.push_back(b.z0);
    prism_z1.push_back(b.z1);
  }
  for (const Cylinder& c : scene.cylinders) {
    prism_z0.push_back(c.z0);
    prism_z1.push_back(c.z1);
  }
  const double ox = pose.x, oy = pose.y;
  std::vector<Candidate> cands;
  cands.reserve(prism_z0.size() + scene.spheres.size());

  for (std::size_t j = 0; j < n_az; ++j) {
    // Horizontal direction in the ground frame: sensor azimuth rotated by the sensor's yaw.
    const double ux = pose.cos_yaw * az_cos[j] - pose.sin_yaw * az_sin[j];
    const double uy = pose.sin_yaw * az_cos[j] + pose.cos_yaw * az_sin[j];

    crossed_2d(scene, ox, oy, ux, uy, cands);
    // Nearest first, so the ring loop can stop early. (The order of equal s_in does not matter:
    // the result is the minimum hit distance, whichever primitive provides it.)
    std::sort(cands.begin(), cands.end(), [](const Candidate& a, const Candidate& b) { return a.s_in < b.s_in; });

    for (std::size_t r = 0; r < n_rings; ++r) {
      const Ring& ring = rings[r];
      const double best = first_hit(scene, ring, cands, prism_z0, prism_z1, ox, oy, ux, uy, max_range);
      const double range = best / ring.cos_e;
      if (range <= max_range) out[r * n_az + j] = range;
    }
  }
}

// Turns ranges into points of the sensor frame (ring-major order), with range noise.
PointCloud make_points(const std::vector<double>& ranges, const std::vector<Ring>& rings,
                       const std::vector<double>& az_cos, const std::vector<double>& az_sin,
                       const SyntheticConfig& config, Rng& noise) {
  PointCloud cloud;
  cloud.reserve(ranges.size());
  const std::size_t n_az = az_cos.size();
  for (std::size_t r = 0; r < rings.size(); ++r) {
    for (std::size_t j = 0; j < n_az; ++j) {
      // One draw per ray, hit or not: the noise of a ray does not depend on the scene.
      const double n = noise.normal() * static_cast<double>(config.range_noise_m);
      const double range = ranges[r * n_az + j];
      if (range < 0.0 || range < config.min_range_m) continue;
      const double noisy = range + n;
      if (noisy < config.min_range_m || noisy > config.max_range_m) continue;
      const double horizontal = noisy * rings[r].cos_e;
      cloud.push_back(Point3{static_cast<float>(horizontal * az_cos[j]), static_cast<float>(horizontal * az_sin[j]),
                             static_cast<float>(noisy * rings[r].sin_e)});
    }
  }
  return cloud;
}

void check_config(const SyntheticConfig& c) {
  std::ostringstream err;
  if (c.rings < 1 || c.rings > 1024) err << "rings must be in 1..1024 (got " << c.rings << "); ";
  if (c.azimuth_steps < 1 || c.azimuth_steps > 100000)
    err << "azimuth_steps must be in 1..100000 (got " << c.azimuth_steps << "); ";
  if (!(c.min_range_m >= 0.0f) || !(c.max_range_m > c.min_range_m) || !std::isfinite(c.max_range_m))
    err << "need 0 <= min_range_m < max_range_m (got " << c.min_range_m << ", " << c.max_range_m << "); ";
  if (!(c.range_noise_m >= 0.0f) || !std::isfinite(c.range_noise_m))
    err << "range_noise_m must be finite and >= 0 (got " << c.range_noise_m << "); ";
  if (!std::isfinite(c.forward_m) || std::fabs(c.forward_m) > 20.0f)
    err << "forward_m must be within [-20, 20] m (got " << c.forward_m << "); ";
  if (!std::isfinite(c.yaw_deg) || std::fabs(c.yaw_deg) > 360.0f)
    err << "yaw_deg must be within [-360, 360] (got " << c.yaw_deg << "); ";
  const std::string msg = err.str();
  if (!msg.empty()) throw InputError("synthetic scene: " + msg.substr(0, msg.size() - 2));
}

}  // namespace

SyntheticPair make_synthetic_pair(const SyntheticConfig& config) {
  check_config(config);
  const Scene scene = make_scene(config.seed);

  std::vector<Ring> rings;
  for (double e : hdl64e_elevations_deg(config.rings)) {
    Ring ring{};
    det_sincos(det_radians(e), ring.sin_e, ring.cos_e);
    ring.tan_e = ring.sin_e / ring.cos_e;
    rings.push_back(ring);
  }
  const std::size_t n_az = static_cast<std::size_t>(config.azimuth_steps);
  std::vector<double> az_cos(n_az), az_sin(n_az);
  for (std::size_t j = 0; j < n_az; ++j)
    det_sincos(det_radians(360.0 * static_cast<double>(j) / static_cast<double>(n_az)), az_sin[j], az_cos[j]);

  double cos_yaw = 1.0, sin_yaw = 0.0;
  det_sincos(det_radians(static_cast<double>(config.yaw_deg)), sin_yaw, cos_yaw);
  const double forward = static_cast<double>(config.forward_m);
  const double max_range = static_cast<double>(config.max_range_m);

  SyntheticPair pair;
  std::vector<double> ranges;
  {
    cast_scan(scene, Pose{0.0, 0.0, 1.0, 0.0}, rings, az_cos, az_sin, max_range, ranges);
    Rng noise(config.seed, kNoiseFrame0);
    pair.frame0 = make_points(ranges, rings, az_cos, az_sin, config, noise);
  }
  {
    cast_scan(scene, Pose{forward, 0.0, cos_yaw, sin_yaw}, rings, az_cos, az_sin, max_range, ranges);
    Rng noise(config.seed, kNoiseFrame1);
    pair.frame1 = make_points(ranges, rings, az_cos, az_sin, config, noise);
  }
  // p0 = R(yaw) p1 + (forward, 0, 0): both sensors are 1.73 m above the same ground.
  const float c = static_cast<float>(cos_yaw), s = static_cast<float>(sin_yaw);
  // clang-format off
  pair.frame1_to_frame0 = Transform{c,    -s,   0.0f, static_cast<float>(forward),
                                    s,    c,    0.0f, 0.0f,
                                    0.0f, 0.0f, 1.0f, 0.0f,
                                    0.0f, 0.0f, 0.0f, 1.0f};
  // clang-format on
  return pair;
}

}  // namespace tigris
