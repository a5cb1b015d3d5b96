// The drive's route and speed profile (see route.hpp).
#include "route.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "det_math.hpp"

namespace tigris::synth {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kEdgeMargin = 150.0;
constexpr double kBrake = 2.5;  // m/s^2, planned deceleration
constexpr double kStep = 0.01;  // s, integration step (10 a frame)
enum Tag : std::uint64_t { kRouteTag = 201 };

struct Heading {
  double hx, hy;
};
Heading left_of(Heading h) { return {-h.hy, h.hx}; }
Heading right_of(Heading h) { return {h.hy, -h.hx}; }

}  // namespace

void Route::at(double s, double& x, double& y, double& hx, double& hy) const {
  s = std::min(std::max(s, 0.0), length());
  auto it = std::upper_bound(pieces.begin(), pieces.end(), s, [](double v, const RoutePiece& p) { return v < p.s0; });
  const RoutePiece& p = *(it == pieces.begin() ? it : it - 1);
  const double d = s - p.s0;
  if (p.turn == 0) {
    x = p.x + p.hx * d;
    y = p.y + p.hy * d;
    hx = p.hx;
    hy = p.hy;
    return;
  }
  // Quarter circle about the centre on the turn's side; rotate by turn * phi.
  const double cx = p.x + p.turn * p.radius * -p.hy, cy = p.y + p.turn * p.radius * p.hx;
  double sn = 0, cs = 1;
  det::det_sincos(d / p.radius, sn, cs);
  sn *= p.turn;
  const double rx = p.x - cx, ry = p.y - cy;
  x = cx + (cs * rx - sn * ry);
  y = cy + (sn * rx + cs * ry);
  hx = cs * p.hx - sn * p.hy;
  hy = sn * p.hx + cs * p.hy;
}

namespace {

// A turn at the crossing street `c`: the straight up to the corner, the quarter arc and the
// corner's speed limit into `route`; the state (axis, k, m, heading, the straight's start and arc
// length, as plan_route keeps them) moves onto the crossing street. Returns the arc's start.
double take_turn(Route& route, const Street& c, int turn, int& axis, int& k, int& m, Heading& h, double& sx, double& sy,
                 double& s0) {
  const auto dir_of = [](Heading v, int a) { return a == 0 ? v.hx : v.hy; };
  const Heading nh = turn > 0 ? left_of(h) : right_of(h);
  const double radius = turn > 0 ? 11.0 : 7.0;
  // The corner: where the current lane line meets the new street's lane line.
  const double lane_new = c.pos + kLaneOffset * (axis == 0 ? right_of(nh).hx : right_of(nh).hy);
  double cx = sx, cy = sy;
  (axis == 0 ? cx : cy) = lane_new;
  const double in_x = cx - radius * h.hx, in_y = cy - radius * h.hy;
  const double straight = (in_x - sx) * h.hx + (in_y - sy) * h.hy;
  if (!(straight > 1.0)) throw std::logic_error("synthetic route: a turn closer than its radius (a bug)");
  route.pieces.push_back(RoutePiece{s0, straight, sx, sy, h.hx, h.hy, 0, 0.0});
  const double s_arc = s0 + straight, arc = 0.5 * kPi * radius;
  route.pieces.push_back(RoutePiece{s_arc, arc, in_x, in_y, h.hx, h.hy, turn, radius});
  SpeedLimit l;
  l.s_from = s_arc;
  l.s_to = s_arc + arc;
  l.v_max = turn > 0 ? 6.0 : 4.5;
  route.limits.push_back(l);
  // Continue on the crossing street from the corner's exit.
  sx = cx + radius * nh.hx;
  sy = cy + radius * nh.hy;
  s0 = s_arc + arc;
  const int new_k = m;
  m = k + static_cast<int>(dir_of(nh, 1 - axis));
  k = new_k;
  axis = 1 - axis;
  h = nh;
  return s_arc;
}

}  // namespace

Route plan_route(std::uint64_t seed, const StreetGrid& grid, double min_length_m) {
  det::Rng rng(seed, stream_id(kRouteTag, 0, 0));
  const std::vector<Street>* across[2] = {&grid.xs(), &grid.ys()};  // the crossings
  Route route;
  // State: travelling along `axis` (0: x, 1: y) on street `k` of along[axis], heading h, the next
  // crossing is street m of across[axis]; the current straight starts at (sx, sy), arc length s0.
  int axis = 0, k = grid.y0_index(), m = grid.x0_index();
  Heading h{1.0, 0.0};
  double sx = 0.0, sy = -kLaneOffset, s0 = 0.0;
  const auto coord = [](double x, double y, int a) { return a == 0 ? x : y; };
  const auto dir_of = [](Heading v, int a) { return a == 0 ? v.hx : v.hy; };
  const auto inside = [&](int a, int next) {  // crossing `next` of across[a] exists, away from the edge
    const std::vector<Street>& c = *across[a];
    return next >= 0 && next < static_cast<int>(c.size()) &&
           std::abs(c[static_cast<std::size_t>(next)].pos) <= kTownHalfSize - kEdgeMargin;
  };
  bool first = true;
  double cruise_from = 0.0;
  double cruise = rng.uniform(7.0, 14.0), accel = rng.uniform(1.0, 2.5);
  const auto add_cruise = [&](double to) {
    SpeedLimit l;
    l.s_from = cruise_from;
    l.s_to = to;
    l.v_max = cruise;
    l.cruise = true;
    l.accel = accel;
    route.limits.push_back(l);
  };
  while (true) {
    const Street& c = (*across[axis])[static_cast<std::size_t>(m)];
    const double dir = dir_of(h, axis);
    const double s_cross = s0 + (c.pos - coord(sx, sy, axis)) * dir;
    if (s_cross >= min_length_m + 50.0) {  // close the last straight past the required length
      route.pieces.push_back(RoutePiece{s0, s_cross - s0, sx, sy, h.hx, h.hy, 0, 0.0});
      add_cruise(s_cross);
      break;
    }
    // One draw each, whatever is decided: the stream stays aligned.
    const double pick = rng.uniform();
    const bool stop = rng.chance(0.35) && !first;
    const double dwell = rng.uniform(1.0, 4.0);
    const double next_cruise = rng.uniform(7.0, 14.0), next_accel = rng.uniform(1.0, 2.5);
    int turn = first ? 0 : (pick < 0.25 ? +1 : (pick < 0.5 ? -1 : 0));
    first = false;
    const int straight_next = m + static_cast<int>(dir);
    const auto turn_ok = [&](int t) {
      const Heading nh = t > 0 ? left_of(h) : right_of(h);
      return inside(1 - axis, k + static_cast<int>(dir_of(nh, 1 - axis)));
    };
    if ((turn == 0 && !inside(axis, straight_next)) || (turn != 0 && !turn_ok(turn))) {
      turn = inside(axis, straight_next) ? 0 : (turn_ok(+1) ? +1 : -1);
    }
    double s_stop = s_cross - (c.half_width + 3.0);
    if (turn == 0) {
      m = straight_next;
    } else {
      s_stop = std::min(s_stop, take_turn(route, c, turn, axis, k, m, h, sx, sy, s0) - 0.5);
    }
    if (stop) {
      SpeedLimit l;
      l.s_from = l.s_to = s_stop;
      l.stop = true;
      l.dwell_s = dwell;
      route.limits.push_back(l);
    }
    // A new target speed from the crossing on (after a turn: from the turn's exit).
    const double change = turn == 0 ? s_cross : s0;
    add_cruise(change);
    cruise_from = change;
    cruise = next_cruise;
    accel = next_accel;
  }
  std::stable_sort(route.limits.begin(), route.limits.end(),
                   [](const SpeedLimit& a, const SpeedLimit& b) { return a.s_from < b.s_from; });
  return route;
}

std::vector<ProfileSample> speed_profile(const Route& route, int frames) {
  const std::vector<SpeedLimit>& lim = route.limits;
  std::vector<bool> passed(lim.size(), false);  // stops already made
  std::vector<ProfileSample> out;
  out.reserve(static_cast<std::size_t>(frames));
  double s = 0.0, v = lim.empty() ? 0.0 : lim.front().v_max;
  int dwell_steps = 0;
  std::size_t held = lim.size();  // the stop being made, if any
  std::size_t from = 0;           // limits before this one are behind the car for good
  for (int f = 0; f < frames; ++f) {
    out.push_back(ProfileSample{s, v});
    for (int step = 0; step < 10; ++step) {
      if (dwell_steps > 0) {
        if (--dwell_steps == 0) passed[held] = true;
        continue;
      }
      // The tightest limit here and ahead (braking curves), and the acceleration of the stretch.
      double allow = 15.0, accel = 1.5;
      std::size_t next_stop = lim.size();
      while (from < lim.size() && (lim[from].stop ? passed[from] : lim[from].s_to < s)) ++from;
      for (std::size_t i = from; i < lim.size(); ++i) {
        const SpeedLimit& l = lim[i];
        if (l.s_from - s > 60.0) break;
        if ((l.stop && passed[i]) || (!l.stop && l.s_to < s)) continue;
        if (l.stop && next_stop == lim.size()) next_stop = i;
        if (s >= l.s_from) {
          allow = std::min(allow, l.v_max);
          if (l.cruise) accel = l.accel;  // the stretch the car is on
        } else {
          allow = std::min(allow, std::sqrt(l.v_max * l.v_max + 2.0 * kBrake * (l.s_from - s)));
        }
      }
      double nv = std::max(0.0, std::min(v + accel * kStep, allow));
      if (next_stop < lim.size()) {
        const double left = lim[next_stop].s_from - s;
        if (nv * kStep >= left - 1e-6 || (left < 0.05 && nv < 0.05)) {  // arrives: hold at the line
          s = lim[next_stop].s_from;
          v = 0.0;
          held = next_stop;
          dwell_steps = std::max(1, static_cast<int>(lim[next_stop].dwell_s / kStep + 0.5));
          continue;
        }
      }
      v = nv;
      s += v * kStep;
    }
  }
  if (s > route.length()) throw std::logic_error("synthetic drive: the route is shorter than the drive (a bug)");
  return out;
}

}  // namespace tigris::synth
