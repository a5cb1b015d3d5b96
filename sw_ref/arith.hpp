// The numeric contract (docs/model.md): the only arithmetic the golden model and the
// hardware model share. Every operation is float32; the build uses -ffp-contract=off so the
// compiler never fuses a multiply-add (which would change the last bit of dist2).
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace tigris {

struct Point3 {
  float x = 0.0f, y = 0.0f, z = 0.0f;
  float operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
};

// ((dx*dx) + (dy*dy)) + (dz*dz), in this order, in float32.
inline float dist2(const Point3& a, const Point3& b) {
  const float dx = a.x - b.x;
  const float dy = a.y - b.y;
  const float dz = a.z - b.z;
  return ((dx * dx) + (dy * dy)) + (dz * dz);
}

// Squared distance from a query to a split plane: (q[axis] - p[axis])^2 in float32.
inline float plane_dist2(const Point3& q, const Point3& p, int axis) {
  const float d = q[axis] - p[axis];
  return d * d;
}

// r2 = r*r in float32 (docs/model.md, numeric contract).
inline float square(float r) { return r * r; }

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// A neighbour: the point's input index and its dist2 to the query.
struct Neighbor {
  std::uint32_t index = 0;
  float dist2 = 0.0f;
};

// Canonical neighbour order: (dist2, index) lexicographically.
inline bool closer(const Neighbor& a, const Neighbor& b) {
  return a.dist2 < b.dist2 || (a.dist2 == b.dist2 && a.index < b.index);
}

// The same order as a function object, for std algorithms (a function pointer is not inlined).
struct Closer {
  bool operator()(const Neighbor& a, const Neighbor& b) const { return closer(a, b); }
};

// Keeps `list` the k best (ascending, canonical order) after offering `n`: what every exact
// kNN search of the golden model does with a candidate.
inline void offer_k_best(std::vector<Neighbor>& list, std::size_t k, const Neighbor& n) {
  if (list.size() == k) {
    if (!closer(n, list.back())) return;
    list.pop_back();
  }
  list.insert(std::upper_bound(list.begin(), list.end(), n, Closer{}), n);
}

}  // namespace tigris
