// Shared helpers for the tests: deterministic random clouds with the awkward cases the golden
// model must survive (duplicates, all-equal, collinear points, points on split planes).
#pragma once

#include <cstdint>
#include <cstring>
#include <random>
#include <string>

#include "sw_ref/cloud.hpp"

namespace tigris::test {

// A float's bit pattern (bit-exact comparisons: -0 and NaN payloads count).
inline std::uint32_t bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

// The same points, coordinate by coordinate, bit for bit.
inline bool same_bits(const PointCloud& a, const PointCloud& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (bits(a[i].x) != bits(b[i].x) || bits(a[i].y) != bits(b[i].y) || bits(a[i].z) != bits(b[i].z)) return false;
  return true;
}

// A portable uniform float in [lo, hi) from 24 random bits (std distributions are not portable).
inline float uniform(std::mt19937_64& rng, float lo, float hi) {
  const float u = static_cast<float>(rng() >> 40) * (1.0f / 16777216.0f);
  return lo + (hi - lo) * u;
}

enum class CloudKind { Uniform, Duplicates, AllEqual, Collinear, Grid };

inline const char* name(CloudKind k) {
  switch (k) {
    case CloudKind::Uniform: return "uniform";
    case CloudKind::Duplicates: return "duplicates";
    case CloudKind::AllEqual: return "all-equal";
    case CloudKind::Collinear: return "collinear";
    default: return "grid";
  }
}

inline PointCloud make_cloud(CloudKind kind, std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  PointCloud c;
  c.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    switch (kind) {
      case CloudKind::Uniform: c.push_back({uniform(rng, -10, 10), uniform(rng, -5, 5), uniform(rng, -1, 2)}); break;
      case CloudKind::Duplicates:  // a few distinct points, each repeated many times
        if (i < 8 || rng() % 3 == 0)
          c.push_back({uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2)});
        else
          c.push_back(c[rng() % c.size()]);
        break;
      case CloudKind::AllEqual: c.push_back({1.5f, -0.25f, 3.0f}); break;
      case CloudKind::Collinear: {
        const float t = uniform(rng, -20, 20);
        c.push_back({t, 0.5f * t, 0.25f});
        break;
      }
      case CloudKind::Grid:  // integer lattice: many points lie exactly on split planes
        c.push_back({static_cast<float>(rng() % 7), static_cast<float>(rng() % 5), static_cast<float>(rng() % 3)});
        break;
    }
  }
  return c;
}

// Queries: random points around the cloud, copies of cloud points (distance 0, ties), and
// lattice points (on split planes).
inline PointCloud make_queries(const PointCloud& cloud, std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ull);
  PointCloud q;
  for (std::size_t i = 0; i < n; ++i) {
    switch (i % 3) {
      case 0: q.push_back({uniform(rng, -12, 12), uniform(rng, -7, 7), uniform(rng, -2, 3)}); break;
      case 1: q.push_back(cloud[rng() % cloud.size()]); break;
      default:
        q.push_back({static_cast<float>(rng() % 7), static_cast<float>(rng() % 5), static_cast<float>(rng() % 3)});
    }
  }
  return q;
}

}  // namespace tigris::test
