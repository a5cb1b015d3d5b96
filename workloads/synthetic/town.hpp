// The synthetic town of the drive (drive.hpp): a seeded grid of streets on gently sloped ground,
// city blocks lined with buildings (setbacks, gaps, a park now and then), parked cars at the
// curbs, poles and trees on the sidewalks. Internal to workloads/synthetic.
//
// Coordinates: x east, y north, z up, metres. Streets run along x (at y = ys[j]) and along y (at
// x = xs[i]); street k of an axis has a half width (centre line to curb) and a sidewalk. The grid
// is fixed by the seed alone: street i's position and width come from its own random stream, and
// so does block (i, j)'s content, so a longer drive sees the same town as a shorter one.
#pragma once

#include <cstdint>
#include <vector>

namespace tigris::synth {

// Ground height z = a x + b y + c x^2 + d y^2 + e x y: slopes of a few percent near the start,
// at most ~13% where the car can go (|x|, |y| <= kTownHalfSize - 150 m), and a ray meets it in a
// quadratic equation.
struct Ground {
  double a = 0, b = 0, c = 0, d = 0, e = 0;
  double height(double x, double y) const { return ((a * x + b * y) + (c * x * x + d * y * y)) + e * x * y; }
  double dx(double x, double y) const { return (a + 2.0 * c * x) + e * y; }  // dz/dx
  double dy(double x, double y) const { return (b + 2.0 * d * y) + e * x; }  // dz/dy
};

struct Box {  // axis-aligned
  double x0, x1, y0, y1, z0, z1;
};
struct Cylinder {  // vertical, capped
  double cx, cy, r, z0, z1;
};
struct Sphere {
  double cx, cy, cz, r;
};

struct Street {
  double pos;         // centre line: y of a street along x, x of a street along y
  double half_width;  // centre line to curb
  double sidewalk;    // curb to the building line
};

constexpr double kTownHalfSize = 1000.0;  // the grid covers [-1000, 1000] m on both axes
constexpr double kLaneOffset = 1.8;       // right-hand traffic: lane centre 1.8 m right of the centre line

class StreetGrid {
 public:
  explicit StreetGrid(std::uint64_t seed);
  // Streets along y (their x positions), ascending, from beyond -kTownHalfSize to beyond +kTownHalfSize.
  const std::vector<Street>& xs() const { return xs_; }
  // Streets along x (their y positions), ascending; the drive starts on the one at y = 0.
  const std::vector<Street>& ys() const { return ys_; }
  int x0_index() const { return x0_; }  // index in xs() of the first street east of the start
  int y0_index() const { return y0_; }  // index in ys() of the street at y = 0

 private:
  std::vector<Street> xs_, ys_;
  int x0_ = 0, y0_ = 0;
};

struct Town {
  Ground ground;
  std::vector<Box> boxes;
  std::vector<Cylinder> cylinders;
  std::vector<Sphere> spheres;
};

Ground make_ground(std::uint64_t seed);

// Fills every block of `grid` whose area comes within `reach` metres of one of the points
// (x, y pairs), in a fixed block order: the town a drive along those points can see.
Town make_town(std::uint64_t seed, const StreetGrid& grid, const std::vector<double>& xy, double reach);

// An independent random stream id for (tag, a, b).
std::uint64_t stream_id(std::uint64_t tag, std::int64_t a, std::int64_t b);

}  // namespace tigris::synth
