// Each leaf set's bounding box: a host-side speed-up, no hardware. A PE scan all of whose
// distances exceed its query's bound (NN/kNN) or radius changes nothing, so the simulator may
// skip computing them; the stream is timed and counted as before.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "hw/tree_view.hpp"
#include "sw_ref/arith.hpp"

namespace tigris::hw {

class LeafBounds {
 public:
  struct Box {
    Point3 lo, hi;
  };

  // A job starts: the boxes of the leaf sets now in the Point Buffer.
  void build(const TreeView& tree, std::uint32_t leaves) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    boxes_.assign(leaves, Box{{inf, inf, inf}, {-inf, -inf, -inf}});
    for (std::uint32_t l = 0; l < leaves; ++l) {
      Box& b = boxes_[l];
      const tlm_if::PointEntry* e = tree.leaf_entries() + tree.leaf_begin(l);
      for (std::uint32_t i = 0, n = tree.leaf_size(l); i < n; ++i) {
        b.lo = {std::min(b.lo.x, e[i].x), std::min(b.lo.y, e[i].y), std::min(b.lo.z, e[i].z)};
        b.hi = {std::max(b.hi.x, e[i].x), std::max(b.hi.y, e[i].y), std::max(b.hi.z, e[i].z)};
      }
    }
  }
  const Box& box(std::uint32_t leaf) const { return boxes_[leaf]; }

  // A lower bound of dist2(q, p), as the PEs compute it in float, for every p in `b`. Rounding
  // is monotone, so each step of dist2 (difference, square, sum) is at least its value for the
  // gap between q and the box's nearest face: no epsilon, no false skip.
  static float min_dist2(const Point3& q, const Box& b) {
    const float gx = q.x < b.lo.x ? b.lo.x - q.x : (q.x > b.hi.x ? q.x - b.hi.x : 0.0f);
    const float gy = q.y < b.lo.y ? b.lo.y - q.y : (q.y > b.hi.y ? q.y - b.hi.y : 0.0f);
    const float gz = q.z < b.lo.z ? b.lo.z - q.z : (q.z > b.hi.z ? q.z - b.hi.z : 0.0f);
    return ((gx * gx) + (gy * gy)) + (gz * gz);
  }

 private:
  std::vector<Box> boxes_;
};

}  // namespace tigris::hw
