// The synthetic town (see town.hpp).
#include "town.hpp"

#include <algorithm>
#include <cmath>

#include "det_math.hpp"

namespace tigris::synth {
namespace {

using det::Rng;

enum Tag : std::uint64_t { kGroundTag = 101, kStreetsTag = 102, kBlockTag = 103 };

Street make_street(Rng& rng, double pos) {
  Street s{pos, 0.0, 0.0};
  s.half_width = rng.uniform(5.5, 7.5);
  s.sidewalk = rng.uniform(2.5, 4.0);
  return s;
}

// Streets of one axis: `first` at a fixed position, then one every 60-110 m both ways to the
// edge of the town.
std::vector<Street> axis_streets(std::uint64_t seed, std::uint64_t axis, double first, int& first_index) {
  Rng east(seed, stream_id(kStreetsTag, static_cast<std::int64_t>(axis), 1));
  Rng west(seed, stream_id(kStreetsTag, static_cast<std::int64_t>(axis), -1));
  std::vector<Street> up{make_street(east, first)}, down;
  while (up.back().pos < kTownHalfSize) up.push_back(make_street(east, up.back().pos + east.uniform(60.0, 110.0)));
  double pos = first;
  while (pos > -kTownHalfSize) {
    pos -= west.uniform(60.0, 110.0);
    down.push_back(make_street(west, pos));
  }
  std::reverse(down.begin(), down.end());
  first_index = static_cast<int>(down.size());
  down.insert(down.end(), up.begin(), up.end());
  return down;
}

struct Rect {
  double x0, x1, y0, y1;
};

// Squared distance from (x, y) to the rectangle (0 inside).
double dist2(const Rect& r, double x, double y) {
  const double dx = x < r.x0 ? r.x0 - x : (x > r.x1 ? x - r.x1 : 0.0);
  const double dy = y < r.y0 ? r.y0 - y : (y > r.y1 ? y - r.y1 : 0.0);
  return dx * dx + dy * dy;
}

class BlockFiller {
 public:
  BlockFiller(Town& town, Rng& rng) : town_(town), g_(town.ground), rng_(rng) {}

  // A box standing on the ground with its top `height` above the ground at its centre; its
  // foot reaches 1 m below the lowest ground under it (the ground hides what is underneath).
  void box(double x0, double x1, double y0, double y1, double height) {
    const double low =
        std::min(std::min(g_.height(x0, y0), g_.height(x1, y0)), std::min(g_.height(x0, y1), g_.height(x1, y1)));
    town_.boxes.push_back(Box{x0, x1, y0, y1, low - 1.0, g_.height(0.5 * (x0 + x1), 0.5 * (y0 + y1)) + height});
  }
  void pole(double x, double y, double r, double height) {
    const double z = g_.height(x, y);
    town_.cylinders.push_back(Cylinder{x, y, r, z - 0.5, z + height});
  }
  void tree(double x, double y) {
    const double trunk_h = rng_.uniform(2.2, 3.5);
    const double crown_r = rng_.uniform(1.2, 2.2);
    const double trunk_r = rng_.uniform(0.12, 0.25);
    pole(x, y, trunk_r, trunk_h);
    town_.spheres.push_back(Sphere{x, y, g_.height(x, y) + trunk_h + 0.7 * crown_r, crown_r});
  }

  // Buildings along one edge of a block. The facade runs along `along` (0: x, 1: y) from a to b
  // at `facade`; the buildings extend towards `inward` (+1 or -1), at most `max_depth` deep.
  void building_row(int along, double a, double b, double facade, int inward, double max_depth) {
    double u = a;
    while (u < b - 1.0) {
      double end = std::min(u + rng_.uniform(8.0, 25.0), b);
      if (b - end < 4.0) end = b;  // no sliver buildings at the end of a row
      const double setback = rng_.chance(0.5) ? 0.0 : rng_.uniform(0.0, 3.0);
      const double depth = std::min(rng_.uniform(10.0, 20.0), max_depth);
      const double height = rng_.uniform(6.0, 22.0);
      const double near = facade + inward * setback, far = facade + inward * (setback + depth);
      const double v0 = std::min(near, far), v1 = std::max(near, far);
      if (along == 0)
        box(u, end, v0, v1, height);
      else
        box(v0, v1, u, end, height);
      u = end;
      if (!rng_.chance(0.35)) u += rng_.uniform(1.5, 6.0);  // a gap between buildings
    }
  }

  // Parked cars, poles and trees along one curb of a street segment [a, b] (along `along`);
  // the curb is at `curb`, the sidewalk on the side `outward` (+1 / -1) of it.
  void curb_side(int along, double a, double b, double curb, int outward, double sidewalk) {
    const auto at = [along](double u, double v, double& x, double& y) {
      x = along == 0 ? u : v;
      y = along == 0 ? v : u;
    };
    double x = 0, y = 0;
    for (double u = a + 8.0; u < b - 8.0;) {  // no parking near the crossings
      if (rng_.chance(0.6)) {
        const bool van = rng_.chance(0.12);
        const double length = van ? rng_.uniform(5.0, 6.0) : rng_.uniform(3.9, 4.6);
        const double width = van ? rng_.uniform(1.9, 2.0) : rng_.uniform(1.7, 1.9);
        const double height = van ? rng_.uniform(2.0, 2.4) : rng_.uniform(1.4, 1.6);
        if (u + length > b - 8.0) break;
        const double v = curb - outward * (0.25 + 0.5 * width);
        at(u + 0.5 * length, v, x, y);
        const double hl = 0.5 * (along == 0 ? length : width), hw = 0.5 * (along == 0 ? width : length);
        box(x - hl, x + hl, y - hw, y + hw, height);
        u += length + rng_.uniform(0.8, 3.0);
      } else {
        u += rng_.uniform(2.0, 6.0);
      }
    }
    for (double u = a + rng_.uniform(2.0, 10.0); u < b - 2.0; u += rng_.uniform(15.0, 25.0)) {
      const double v = curb + outward * rng_.uniform(0.4, 0.7);
      at(u, v, x, y);
      const double r = rng_.uniform(0.08, 0.15);
      pole(x, y, r, rng_.uniform(5.0, 9.0));
    }
    for (double u = a + rng_.uniform(3.0, 12.0); u < b - 3.0; u += rng_.uniform(8.0, 20.0)) {
      if (!rng_.chance(0.5)) continue;
      const double v = curb + outward * std::min(rng_.uniform(1.2, 1.8), sidewalk - 0.3);
      at(u, v, x, y);
      tree(x, y);
    }
  }

 private:
  Town& town_;
  const Ground& g_;
  Rng& rng_;
};

}  // namespace

std::uint64_t stream_id(std::uint64_t tag, std::int64_t a, std::int64_t b) {
  return det::splitmix64(
      tag ^ det::splitmix64(static_cast<std::uint64_t>(a) ^ det::splitmix64(static_cast<std::uint64_t>(b))));
}

Ground make_ground(std::uint64_t seed) {
  Rng rng(seed, stream_id(kGroundTag, 0, 0));
  Ground g;
  g.a = rng.uniform(-0.025, 0.025);
  g.b = rng.uniform(-0.025, 0.025);
  g.c = rng.uniform(-2.5e-5, 2.5e-5);
  g.d = rng.uniform(-2.5e-5, 2.5e-5);
  g.e = rng.uniform(-2.5e-5, 2.5e-5);
  return g;
}

StreetGrid::StreetGrid(std::uint64_t seed) {
  Rng first(seed, stream_id(kStreetsTag, 2, 0));
  xs_ = axis_streets(seed, 0, first.uniform(30.0, 70.0), x0_);
  ys_ = axis_streets(seed, 1, 0.0, y0_);
}

Town make_town(std::uint64_t seed, const StreetGrid& grid, const std::vector<double>& xy, double reach) {
  Town town;
  town.ground = make_ground(seed);
  const std::vector<Street>& xs = grid.xs();
  const std::vector<Street>& ys = grid.ys();
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    for (std::size_t j = 0; j + 1 < ys.size(); ++j) {
      // The block between the four streets' centre lines.
      const Rect area{xs[i].pos, xs[i + 1].pos, ys[j].pos, ys[j + 1].pos};
      bool seen = false;
      for (std::size_t k = 0; k + 1 < xy.size() && !seen; k += 2) seen = dist2(area, xy[k], xy[k + 1]) <= reach * reach;
      if (!seen) continue;
      Rng rng(seed, stream_id(kBlockTag, static_cast<std::int64_t>(i) - grid.x0_index(),
                              static_cast<std::int64_t>(j) - grid.y0_index()));
      BlockFiller fill(town, rng);
      // Curbs and building lines.
      const double cx0 = xs[i].pos + xs[i].half_width, cx1 = xs[i + 1].pos - xs[i + 1].half_width;
      const double cy0 = ys[j].pos + ys[j].half_width, cy1 = ys[j + 1].pos - ys[j + 1].half_width;
      const double bx0 = cx0 + xs[i].sidewalk, bx1 = cx1 - xs[i + 1].sidewalk;
      const double by0 = cy0 + ys[j].sidewalk, by1 = cy1 - ys[j + 1].sidewalk;
      if (rng.chance(0.12)) {  // a park: trees on a jittered grid
        for (double x = bx0 + 4.0; x < bx1 - 4.0; x += rng.uniform(7.0, 12.0))
          for (double y = by0 + 4.0; y < by1 - 4.0; y += rng.uniform(7.0, 12.0))
            if (rng.chance(0.6)) {
              const double jx = rng.uniform(-2.0, 2.0);  // one draw a statement: argument order is unspecified
              const double jy = rng.uniform(-2.0, 2.0);
              fill.tree(x + jx, y + jy);
            }
      } else {
        const double half_x = 0.5 * (bx1 - bx0) - 1.0, half_y = 0.5 * (by1 - by0) - 1.0;
        fill.building_row(0, bx0, bx1, by0, +1, half_y);                // south edge, facing the street at ys[j]
        fill.building_row(0, bx0, bx1, by1, -1, half_y);                // north edge
        fill.building_row(1, by0 + 10.0, by1 - 10.0, bx0, +1, half_x);  // west edge
        fill.building_row(1, by0 + 10.0, by1 - 10.0, bx1, -1, half_x);  // east edge
      }
      // The block's four curbs: parked cars, poles, trees.
      fill.curb_side(0, cx0, cx1, cy0, +1, ys[j].sidewalk);
      fill.curb_side(0, cx0, cx1, cy1, -1, ys[j + 1].sidewalk);
      fill.curb_side(1, cy0, cy1, cx0, +1, xs[i].sidewalk);
      fill.curb_side(1, cy0, cy1, cx1, -1, xs[i + 1].sidewalk);
    }
  }
  return town;
}

}  // namespace tigris::synth
