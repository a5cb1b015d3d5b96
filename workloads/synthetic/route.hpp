// The drive's route through the street grid and its speed profile (drive.hpp). Internal to
// workloads/synthetic.
//
// Route: the car keeps to the right lane (kLaneOffset right of the centre line); at each crossing
// it goes straight (1 in 2) or turns left (radius 11 m) or right (7 m) on quarter circles, and
// stops at the stop line for 1-4 s (1 in 3); it never heads for a crossing within 150 m of the town's edge.
// Speed: 7-14 m/s between crossings (a new target after each), 6 m/s in left turns and 4.5 m/s
// in right turns, accelerating at 1-2.5 m/s^2 and braking at 2.5 m/s^2 ahead of a slower stretch
// or a stop. Sampled on a 10 ms step, the frames at every 10th.
#pragma once

#include <cstdint>
#include <vector>

#include "town.hpp"

namespace tigris::synth {

struct RoutePiece {
  double s0 = 0, length = 0;  // arc length where the piece starts, and its length
  double x = 0, y = 0;        // start point
  double hx = 1, hy = 0;      // heading at the start (a unit axis vector)
  int turn = 0;               // 0 straight, +1 left quarter circle, -1 right
  double radius = 0;
};

// v <= v_max on [s_from, s_to]; a stop holds the car at s_from for dwell_s.
struct SpeedLimit {
  double s_from = 0, s_to = 0, v_max = 0;
  bool stop = false;
  double dwell_s = 0;
  bool cruise = false;  // a stretch between crossings (else a turn or a stop)
  double accel = 1.5;   // a cruise stretch's acceleration
};

struct Route {
  std::vector<RoutePiece> pieces;
  std::vector<SpeedLimit> limits;  // sorted by s_from
  double length() const { return pieces.empty() ? 0.0 : pieces.back().s0 + pieces.back().length; }
  // Position and heading (unit, horizontal) at arc length s (clamped to the route).
  void at(double s, double& x, double& y, double& hx, double& hy) const;
};

// A route at least min_length_m long.
Route plan_route(std::uint64_t seed, const StreetGrid& grid, double min_length_m);

struct ProfileSample {
  double s, speed;
};

// The car's arc length and speed at t = 0, 0.1, ... (frames samples); starts at the first
// stretch's cruise speed. Throws std::logic_error if the route is too short (a bug).
std::vector<ProfileSample> speed_profile(const Route& route, int frames);

}  // namespace tigris::synth
