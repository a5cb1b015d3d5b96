// Bit-reproducible elementary functions and random numbers for the synthetic scenes (the pair of
// synthetic.hpp and the drive of synthetic/drive.hpp): the same seed gives the same bits on every
// conforming platform.
//  - Random numbers come from std::mt19937_64 (its output sequence is fixed by the standard);
//    uniform and normal variates are derived here from raw 64-bit draws, never through
//    std::*_distribution (whose algorithms differ between standard libraries).
//  - sin/cos/log are computed here with +, -, *, / and sqrt only (all correctly rounded in IEEE
//    754), never through libm, whose last bits differ between C libraries.
//  - The build uses -ffp-contract=off, so no multiply-add is fused.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace tigris::det {

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// Portable elementary functions (only correctly rounded IEEE operations inside).

// sin and cos of x (radians, |x| < 1e6), about 1 ulp accurate, bit-reproducible everywhere.
inline void det_sincos(double x, double& s, double& c) {
  // Cody-Waite reduction by pi/2 (pi/2 split in a 33-bit head and a tail).
  constexpr double kPio2Hi = 1.57079632673412561417e+00;
  constexpr double kPio2Lo = 6.07710050650619224932e-11;
  constexpr double kTwoOverPi = 6.36619772367581382433e-01;
  const double k = std::floor(x * kTwoOverPi + 0.5);
  const double r = (x - k * kPio2Hi) - k * kPio2Lo;  // |r| <= ~pi/4
  const double r2 = r * r;
  // Taylor series up to r^17 / r^18: the remainder is below 1e-19 for |r| <= pi/4.
  double ps = 1.0 / 355687428096000.0;  // 1/17!
  ps = ps * -r2 + 1.0 / 1307674368000.0;
  ps = ps * -r2 + 1.0 / 6227020800.0;
  ps = ps * -r2 + 1.0 / 39916800.0;
  ps = ps * -r2 + 1.0 / 362880.0;
  ps = ps * -r2 + 1.0 / 5040.0;
  ps = ps * -r2 + 1.0 / 120.0;
  ps = ps * -r2 + 1.0 / 6.0;
  const double sr = r - r * r2 * ps;     // r - r^3/3! + r^5/5! - ...
  double pc = 1.0 / 6402373705728000.0;  // 1/18!
  pc = pc * -r2 + 1.0 / 20922789888000.0;
  pc = pc * -r2 + 1.0 / 87178291200.0;
  pc = pc * -r2 + 1.0 / 479001600.0;
  pc = pc * -r2 + 1.0 / 3628800.0;
  pc = pc * -r2 + 1.0 / 40320.0;
  pc = pc * -r2 + 1.0 / 720.0;
  pc = pc * -r2 + 1.0 / 24.0;
  pc = pc * -r2 + 0.5;
  const double cr = 1.0 - r2 * pc;                  // 1 - r^2/2! + r^4/4! - ...
  const double q = k - 4.0 * std::floor(k * 0.25);  // quadrant 0..3, exact
  if (q == 0.0) {
    s = sr;
    c = cr;
  } else if (q == 1.0) {
    s = cr;
    c = -sr;
  } else if (q == 2.0) {
    s = -sr;
    c = -cr;
  } else {
    s = -cr;
    c = sr;
  }
}

inline double det_radians(double deg) { return deg * (kPi / 180.0); }

// Natural logarithm of x > 0 (finite, normal), bit-reproducible everywhere.
inline double det_log(double x) {
  constexpr double kLn2 = 6.93147180559945286227e-01;
  constexpr double kSqrtHalf = 7.07106781186547524401e-01;
  int e = 0;
  double m = std::frexp(x, &e);  // x = m * 2^e, m in [0.5, 1): exact
  if (m < kSqrtHalf) {
    m *= 2.0;  // exact
    --e;
  }
  // log(m) = 2 atanh(f), f = (m - 1) / (m + 1), |f| <= 0.1716.
  const double f = (m - 1.0) / (m + 1.0);
  const double f2 = f * f;
  double p = 1.0 / 23.0;
  p = p * f2 + 1.0 / 21.0;
  p = p * f2 + 1.0 / 19.0;
  p = p * f2 + 1.0 / 17.0;
  p = p * f2 + 1.0 / 15.0;
  p = p * f2 + 1.0 / 13.0;
  p = p * f2 + 1.0 / 11.0;
  p = p * f2 + 1.0 / 9.0;
  p = p * f2 + 1.0 / 7.0;
  p = p * f2 + 1.0 / 5.0;
  p = p * f2 + 1.0 / 3.0;
  const double log_m = 2.0 * f + 2.0 * f * f2 * p;
  return static_cast<double>(e) * kLn2 + log_m;
}

// ---------------------------------------------------------------------------------------------
// Random numbers.

// SplitMix64 finaliser: derives independent stream seeds from the user's seed.
inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t stream) : engine_(splitmix64(seed ^ splitmix64(stream))) {}

  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  bool chance(double p) { return uniform() < p; }

  // Standard normal variate: Marsaglia's polar method (uses det_log and sqrt only).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u = 0.0, v = 0.0, s = 0.0;
    do {
      u = 2.0 * uniform() - 1.0;
      v = 2.0 * uniform() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double factor = std::sqrt(-2.0 * det_log(s) / s);
    spare_ = v * factor;
    has_spare_ = true;
    return u * factor;
  }

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

// ---------------------------------------------------------------------------------------------
// The scanner.

// The lasers' elevation angles in degrees, ring 0 first (highest): the HDL-64E's for 64 rings,
// else evenly spread over the same +2.0 .. -24.8 degrees.
inline std::vector<double> hdl64e_elevations_deg(int rings) {
  std::vector<double> e(static_cast<std::size_t>(rings));
  if (rings == 64) {
    // HDL-64E: upper block +2.0 .. -8.33 in 1/3 degree steps; lower block -8.83 .. -24.8.
    for (int i = 0; i < 32; ++i) e[static_cast<std::size_t>(i)] = 2.0 - i / 3.0;
    for (int i = 0; i < 32; ++i) e[static_cast<std::size_t>(32 + i)] = -8.83 - i * ((24.8 - 8.83) / 31.0);
  } else {
    for (int i = 0; i < rings; ++i) e[static_cast<std::size_t>(i)] = rings == 1 ? 0.0 : 2.0 - i * (26.8 / (rings - 1));
  }
  return e;
}

}  // namespace tigris::det
