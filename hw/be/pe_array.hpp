// The Search Unit's 1-D systolic PE array (paper section 5.3, Fig. 9): query-stationary, the
// Node Set streams through; each PE's pipeline (read, distance, insert: cost.pe_pipeline_depth
// stages) never stalls. Holds the stream formula and the PEs' function.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

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
  void start(const JobDescriptor& job, TreeView tree, ResultSlots slots) {
    job_ = &job, tree_ = tree, slots_ = slots;
  }
  // The Node Set of `leaf`: its first entry and size.
  const tlm_if::PointEntry* node_set(std::uint32_t leaf) const { return tree_.leaf_entries() + tree_.leaf_begin(leaf); }

  // One PE scans `count` entries (a Node Set, or a leader's local result list) for its query:
  // NN/kNN results go to its Result Buffer slot, radius hits to `hits`. With `local`, the PE
  // also keeps the query's local result list as a new leader (DESIGN.md section 13): its
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

 private:
  static constexpr std::uint32_t kBlock = 16;  // entries whose distances are computed together
  // The distances of `n` <= kBlock entries, in a loop the compiler vectorizes (a host speed-up:
  // the same dist2, bit for bit, as the PEs compute one by one).
  static void distances(const Point3& q, const tlm_if::PointEntry* e, std::uint32_t n, float* d) {
    for (std::uint32_t i = 0; i < n; ++i) d[i] = dist2(q, Point3{e[i].x, e[i].y, e[i].z});
  }

  // NN/kNN. The PE holds its query's k-th best distance: a point farther than it cannot enter
  // the list (equal ones still may, by index), so only closer ones go through the insert. A
  // block none of whose points is within the bound is passed over at once (the bound only falls).
  void scan_nearest(const QueryToken& token, const tlm_if::PointEntry* set, std::uint32_t count) {
    float bound = slots_.bound(token.slot);
    float d[kBlock];
    for (std::uint32_t b = 0; b < count; b += kBlock) {
      const std::uint32_t n = std::min(kBlock, count - b);
      distances(token.point, set + b, n, d);
      bool any = false;
      for (std::uint32_t i = 0; i < n; ++i) any |= d[i] <= bound;
      if (!any) continue;
      for (std::uint32_t i = 0; i < n; ++i)
        if (d[i] <= bound && slots_.insert(token.slot, {set[b + i].tag, d[i]})) bound = slots_.bound(token.slot);
    }
  }
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
    float d[kBlock];
    for (std::uint32_t b = 0; b < count; b += kBlock) {
      const std::uint32_t n = std::min(kBlock, count - b);
      distances(token.point, set + b, n, d);
      for (std::uint32_t i = 0; i < n; ++i) {
        if (!(d[i] <= r2)) continue;
        hits.push_back({token.query, set[b + i].tag, d[i]});
        if (local) local->push_back(set[b + i]);
      }
    }
  }

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
