// The Search Unit's 1-D systolic PE array (paper section 5.3, Fig. 9): query-stationary, the
// Node Set streams through; each PE's pipeline (read, distance, insert: cost.pe_pipeline_depth
// stages) never stalls. Holds the stream formula and the PEs' function.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "hw/job.hpp"
#include "hw/mem/result_slots.hpp"
#include "hw/tree_view.hpp"

namespace tigris::hw {

class PeArray {
 public:
  // Cycles to stream `points` entries past `queries` occupied PEs: the last point enters at
  // points - 1, reaches the last PE queries - 1 later, and leaves its pipeline after `depth`.
  static std::uint64_t stream_cycles(std::uint64_t points, std::uint64_t queries, int depth) {
    return points == 0 || queries == 0 ? 0 : points + queries - 1 + static_cast<std::uint64_t>(depth);
  }
  // The cycle a stream started at `start` ends when its last word arrives at `data_ready`: it
  // cannot run ahead of its data (the last point enters the array once it arrived).
  static std::uint64_t stream_end(std::uint64_t start, std::uint64_t data_ready, std::uint64_t points,
                                  std::uint64_t queries, int depth) {
    return std::max(start + stream_cycles(points, queries, depth),
                    data_ready + queries - 1 + static_cast<std::uint64_t>(depth));
  }

  // A job starts: the Node Sets and result slots as this SU's ports see them.
  void start(const JobDescriptor& job, TreeView tree, ResultSlots slots) { job_ = &job, tree_ = tree, slots_ = slots; }
  const ResultSlots& slots() const { return slots_; }
  // `token`'s search has ended here (a first_leaf follower): its NN/kNN list, closest first,
  // as records for the write-back stream.
  void finish(const QueryToken& token, std::vector<tlm_if::ResultRecord>& out) {
    slots_.finish(token.slot);
    const Neighbor* e = slots_.entries(token.slot);
    for (std::uint32_t i = 0, n = slots_.count(token.slot); i < n; ++i)
      out.push_back({token.query, e[i].index, e[i].dist2});
  }
  // The distance a point must not exceed to enter `slot`'s list (its k-th best so far).
  float bound(std::uint32_t slot) const { return slots_.bound(slot); }
  // The Node Set of `leaf`: its first entry and size.
  const tlm_if::PointEntry* node_set(std::uint32_t leaf) const { return tree_.leaf_entries() + tree_.leaf_begin(leaf); }

  // One PE scans `count` entries (a Node Set, or a leader's local result list) for its query:
  // NN/kNN results go to its Result Buffer slot, radius hits to `hits`. With `local`, the PE
  // also keeps the query's local result list as a new leader (docs/model.md): its
  // in-radius entries (radius) or its job.leader_width best in (dist2, index) order (NN/kNN).
  void scan(const QueryToken& token, const tlm_if::PointEntry* set, std::uint32_t count,
            std::vector<tlm_if::ResultRecord>& hits, std::vector<tlm_if::PointEntry>* local = nullptr) {
    if (job_->radius())
      scan_radius(token, set, count, hits, local);
    else if (local)
      scan_leader(token, set, count, *local);
    else
      scan_nearest(token, set, count);
  }

  // NN/kNN. The PE holds its query's k-th best distance: a point farther than it cannot enter
  // the list (equal ones still may, by index), so only closer ones go through the insert.
  void scan_nearest(const QueryToken& token, const tlm_if::PointEntry* set, std::uint32_t count) {
    float bound = slots_.bound(token.slot);
    std::uint32_t i = 0;
#if defined(__SSE2__)
    const Lanes q(token.point);
    while (i + 4 <= count) {
      // Four entries at a time up to the first within the bound (a loop without calls, so its
      // operands stay in registers), then that block's inserts one by one.
      const __m128 vbound = _mm_set1_ps(bound);
      __m128 d = _mm_setzero_ps();
      int m = 0;
      for (; i + 4 <= count; i += 4) {
        d = q.dist2(set + i);
        m = _mm_movemask_ps(_mm_cmple_ps(d, vbound));
        if (m != 0) break;
      }
      if (m == 0) break;
      alignas(16) float ds[4];
      _mm_store_ps(ds, d);
      for (int l = 0; l < 4; ++l)
        if (((m >> l) & 1) && ds[l] <= bound && slots_.insert(token.slot, {set[i + l].tag, ds[l]}))
          bound = slots_.bound(token.slot);
      i += 4;
    }
#endif
    for (; i < count; ++i) {
      const float d = dist2(token.point, Point3{set[i].x, set[i].y, set[i].z});
      if (d <= bound && slots_.insert(token.slot, {set[i].tag, d})) bound = slots_.bound(token.slot);
    }
  }

 private:
  // NN/kNN for a new leader: also keeps its job.leader_width best as its local list.
  void scan_leader(const QueryToken& token, const tlm_if::PointEntry* set, std::uint32_t count,
                   std::vector<tlm_if::PointEntry>& local) {
    best_.clear();
    float bound = slots_.bound(token.slot);
    for (std::uint32_t i = 0; i < count; ++i) {
      const float d = dist2(token.point, Point3{set[i].x, set[i].y, set[i].z});
      keep_best({set[i].tag, d}, set[i]);
      if (d <= bound && slots_.insert(token.slot, {set[i].tag, d})) bound = slots_.bound(token.slot);
    }
    for (const auto& b : best_) local.push_back(b.second);
  }
  // Radius: every hit is streamed out; a new leader keeps its in-radius entries.
  void scan_radius(const QueryToken& token, const tlm_if::PointEntry* set, std::uint32_t count,
                   std::vector<tlm_if::ResultRecord>& hits, std::vector<tlm_if::PointEntry>* local) {
    const float r2 = job_->r2;
    const auto hit = [&](std::uint32_t i, float d) {
      hits.push_back({token.query, set[i].tag, d});
      if (local) local->push_back(set[i]);
    };
    std::uint32_t i = 0;
#if defined(__SSE2__)
    const Lanes q(token.point);
    const __m128 vr2 = _mm_set1_ps(r2);
    for (; i + 4 <= count; i += 4) {
      const __m128 d = q.dist2(set + i);
      const int m = _mm_movemask_ps(_mm_cmple_ps(d, vr2));
      if (m == 0) continue;
      alignas(16) float ds[4];
      _mm_store_ps(ds, d);
      for (int l = 0; l < 4; ++l)
        if ((m >> l) & 1) hit(i + l, ds[l]);
    }
#endif
    for (; i < count; ++i) {
      const float d = dist2(token.point, Point3{set[i].x, set[i].y, set[i].z});
      if (d <= r2) hit(i, d);
    }
  }

#if defined(__SSE2__)
  // A host speed-up: dist2 of four entries at once, lane by lane the same float operations in
  // the same order as sw_ref/arith.hpp (SSE arithmetic is IEEE single precision), so bit-exact.
  struct Lanes {
    __m128 x, y, z;
    explicit Lanes(const Point3& q) : x(_mm_set1_ps(q.x)), y(_mm_set1_ps(q.y)), z(_mm_set1_ps(q.z)) {}
    __m128 dist2(const tlm_if::PointEntry* e) const {
      const __m128 r0 = _mm_loadu_ps(&e[0].x), r1 = _mm_loadu_ps(&e[1].x);
      const __m128 r2 = _mm_loadu_ps(&e[2].x), r3 = _mm_loadu_ps(&e[3].x);
      const __m128 xy01 = _mm_unpacklo_ps(r0, r1), xy23 = _mm_unpacklo_ps(r2, r3);  // x0 x1 y0 y1
      const __m128 zw01 = _mm_unpackhi_ps(r0, r1), zw23 = _mm_unpackhi_ps(r2, r3);  // z0 z1 w0 w1
      const __m128 dx = _mm_sub_ps(x, _mm_movelh_ps(xy01, xy23));
      const __m128 dy = _mm_sub_ps(y, _mm_movehl_ps(xy23, xy01));
      const __m128 dz = _mm_sub_ps(z, _mm_movelh_ps(zw01, zw23));
      return _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
    }
  };
#endif

  // The leader_width best so far, closest first (insertion into a short sorted list).
  void keep_best(Neighbor n, const tlm_if::PointEntry& e) {
    if (best_.size() == job_->leader_width && !closer(n, best_.back().first)) return;
    if (best_.size() == job_->leader_width) best_.pop_back();
    auto it = best_.end();
    while (it != best_.begin() && closer(n, (it - 1)->first)) --it;
    best_.insert(it, {n, e});
  }

  const JobDescriptor* job_ = nullptr;
  std::vector<std::pair<Neighbor, tlm_if::PointEntry>> best_;
  TreeView tree_;
  ResultSlots slots_;
};

}  // namespace tigris::hw
