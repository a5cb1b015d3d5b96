// The drive's LiDAR (see lidar.hpp). Rays are cast in the town frame. The 64 rays of one azimuth
// nearly share a horizontal direction (exactly, for an upright sensor): per azimuth, a primitive
// is a candidate when its bounding circle meets the wedge of those horizontal directions, and
// candidates are tried nearest first, so a ray stops at the first candidate farther than its
// best hit. The result is the minimum hit distance, whatever the order of equal bounds.
#include "lidar.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace tigris::synth {
namespace {

constexpr double kInf = 1e300;

struct Prim {
  double cx, cy, rho;  // bounding circle in the xy plane
  int kind;            // 0 box, 1 cylinder, 2 sphere
  std::size_t index;
};
struct Candidate {
  double lb;  // lower bound on the ray distance (horizontal distance to the circle)
  const Prim* prim;
};

struct Ray {
  double ox, oy, oz, dx, dy, dz;  // unit direction
};

double hit_box(const Box& b, const Ray& r, double best) {
  double lo = 0.0, hi = best;
  const double o[3] = {r.ox, r.oy, r.oz}, d[3] = {r.dx, r.dy, r.dz};
  const double mn[3] = {b.x0, b.y0, b.z0}, mx[3] = {b.x1, b.y1, b.z1};
  for (int a = 0; a < 3; ++a) {
    if (std::fabs(d[a]) < 1e-15) {
      if (o[a] < mn[a] || o[a] > mx[a]) return kInf;
      continue;
    }
    double t0 = (mn[a] - o[a]) / d[a], t1 = (mx[a] - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0);
    hi = std::min(hi, t1);
    if (lo > hi) return kInf;
  }
  return lo;
}

double hit_cylinder(const Cylinder& c, const Ray& r, double best) {
  const double px = r.ox - c.cx, py = r.oy - c.cy;
  const double a = r.dx * r.dx + r.dy * r.dy;
  if (a < 1e-30) return kInf;
  const double b = px * r.dx + py * r.dy;
  const double disc = b * b - a * ((px * px + py * py) - c.r * c.r);
  if (disc < 0.0) return kInf;
  const double sq = std::sqrt(disc);
  double lo = std::max(0.0, (-b - sq) / a), hi = std::min(best, (-b + sq) / a);
  if (std::fabs(r.dz) < 1e-15) {
    if (r.oz < c.z0 || r.oz > c.z1) return kInf;
  } else {
    double t0 = (c.z0 - r.oz) / r.dz, t1 = (c.z1 - r.oz) / r.dz;
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0);
    hi = std::min(hi, t1);
  }
  return lo <= hi ? lo : kInf;
}

double hit_sphere(const Sphere& s, const Ray& r) {
  const double px = r.ox - s.cx, py = r.oy - s.cy, pz = r.oz - s.cz;
  const double b = (px * r.dx + py * r.dy) + pz * r.dz;
  const double disc = b * b - (((px * px + py * py) + pz * pz) - s.r * s.r);
  if (disc < 0.0) return kInf;
  const double sq = std::sqrt(disc);
  double t = -b - sq;
  if (t < 0.0) t = -b + sq;
  return t < 0.0 ? kInf : t;
}

// The first crossing of the ground z = G(x, y) (the sensor is above it): the quadratic
// A t^2 + B t + C = 0 of G(o + t d) - (oz + t dz), with C < 0.
double hit_ground(const Ground& g, const Ray& r) {
  const double A = (g.c * r.dx * r.dx + g.d * r.dy * r.dy) + g.e * r.dx * r.dy;
  const double B = (g.dx(r.ox, r.oy) * r.dx + g.dy(r.ox, r.oy) * r.dy) - r.dz;
  const double C = g.height(r.ox, r.oy) - r.oz;
  if (std::fabs(A) < 1e-18) return B > 0.0 ? -C / B : kInf;
  const double disc = B * B - 4.0 * A * C;
  if (disc < 0.0) return kInf;
  const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
  double best = kInf;
  for (const double t : {q / A, q != 0.0 ? C / q : kInf})
    if (t > 0.0 && t < best) best = t;
  return best;
}

}  // namespace

PointCloud lidar_scan(const Town& town, const Pose34& pose, const LidarConfig& config, det::Rng& noise) {
  const std::vector<double> elev = det::hdl64e_elevations_deg(config.rings);
  const std::size_t n_rings = elev.size(), n_az = static_cast<std::size_t>(config.azimuth_steps);
  std::vector<double> se(n_rings), ce(n_rings), sa(n_az), ca(n_az);
  for (std::size_t r = 0; r < n_rings; ++r) det::det_sincos(det::det_radians(elev[r]), se[r], ce[r]);
  for (std::size_t j = 0; j < n_az; ++j)
    det::det_sincos(det::det_radians(360.0 * static_cast<double>(j) / static_cast<double>(n_az)), sa[j], ca[j]);

  const double ox = pose[3], oy = pose[7], oz = pose[11];
  const double reach = config.max_range_m + 1.0;
  // Primitives within reach of the sensor, with their bounding circles.
  std::vector<Prim> prims;
  const auto keep = [&](double cx, double cy, double rho, int kind, std::size_t i) {
    const double vx = cx - ox, vy = cy - oy;
    if (std::sqrt(vx * vx + vy * vy) - rho <= reach) prims.push_back(Prim{cx, cy, rho, kind, i});
  };
  for (std::size_t i = 0; i < town.boxes.size(); ++i) {
    const Box& b = town.boxes[i];
    const double hx = 0.5 * (b.x1 - b.x0), hy = 0.5 * (b.y1 - b.y0);
    keep(b.x0 + hx, b.y0 + hy, std::sqrt(hx * hx + hy * hy), 0, i);
  }
  for (std::size_t i = 0; i < town.cylinders.size(); ++i)
    keep(town.cylinders[i].cx, town.cylinders[i].cy, town.cylinders[i].r, 1, i);
  for (std::size_t i = 0; i < town.spheres.size(); ++i)
    keep(town.spheres[i].cx, town.spheres[i].cy, town.spheres[i].r, 2, i);

  std::vector<double> ranges(n_rings * n_az, -1.0);
  std::vector<double> dirs(n_rings * 3);
  std::vector<Candidate> cands;
  cands.reserve(prims.size());
  const std::size_t mid = n_rings / 2;
  for (std::size_t j = 0; j < n_az; ++j) {
    // The column's world directions and the wedge of their horizontal parts.
    for (std::size_t r = 0; r < n_rings; ++r) {
      const double sx = ce[r] * ca[j], sy = ce[r] * sa[j], sz = se[r];
      for (int k = 0; k < 3; ++k) dirs[r * 3 + k] = (pose[4 * k] * sx + pose[4 * k + 1] * sy) + pose[4 * k + 2] * sz;
    }
    const double mn = std::sqrt(dirs[mid * 3] * dirs[mid * 3] + dirs[mid * 3 + 1] * dirs[mid * 3 + 1]);
    const double ux = dirs[mid * 3] / mn, uy = dirs[mid * 3 + 1] / mn;
    double cos_a = 1.0;
    for (std::size_t r = 0; r < n_rings; ++r) {
      const double hx = dirs[r * 3], hy = dirs[r * 3 + 1];
      cos_a = std::min(cos_a, (hx * ux + hy * uy) / std::sqrt(hx * hx + hy * hy));
    }
    const double sin_a = std::sqrt(std::max(0.0, 1.0 - cos_a * cos_a));
    cands.clear();
    for (const Prim& p : prims) {
      const double vx = p.cx - ox, vy = p.cy - oy, rho = p.rho + 0.05;
      const double len = std::sqrt(vx * vx + vy * vy);
      if (len <= rho) {
        cands.push_back(Candidate{0.0, &p});
        continue;
      }
      // Inside the wedge widened by the circle's half angle b: angle(v, u) <= a + b.
      const double sb = rho / len, cb = std::sqrt(1.0 - sb * sb);
      if (vx * ux + vy * uy >= len * (cos_a * cb - sin_a * sb) - 1e-9 * len) cands.push_back(Candidate{len - rho, &p});
    }
    std::sort(cands.begin(), cands.end(), [](const Candidate& a, const Candidate& b) { return a.lb < b.lb; });

    for (std::size_t r = 0; r < n_rings; ++r) {
      const Ray ray{ox, oy, oz, dirs[r * 3], dirs[r * 3 + 1], dirs[r * 3 + 2]};
      double best = std::min(reach, hit_ground(town.ground, ray));
      for (const Candidate& c : cands) {
        if (c.lb >= best) break;
        const Prim& p = *c.prim;
        const double t = p.kind == 0   ? hit_box(town.boxes[p.index], ray, best)
                         : p.kind == 1 ? hit_cylinder(town.cylinders[p.index], ray, best)
                                       : hit_sphere(town.spheres[p.index], ray);
        if (t < best) best = t;
      }
      if (best <= config.max_range_m) ranges[r * n_az + j] = best;
    }
  }

  PointCloud cloud;
  cloud.reserve(ranges.size());
  for (std::size_t r = 0; r < n_rings; ++r) {
    for (std::size_t j = 0; j < n_az; ++j) {
      const double n = noise.normal() * config.range_noise_m;  // one draw per ray, hit or not
      const double range = ranges[r * n_az + j];
      if (range < config.min_range_m) continue;
      const double noisy = range + n;
      if (noisy < config.min_range_m || noisy > config.max_range_m) continue;
      const double horizontal = noisy * ce[r];
      cloud.push_back(Point3{static_cast<float>(horizontal * ca[j]), static_cast<float>(horizontal * sa[j]),
                             static_cast<float>(noisy * se[r])});
    }
  }
  return cloud;
}

}  // namespace tigris::synth
