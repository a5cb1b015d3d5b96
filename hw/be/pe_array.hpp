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
    best_.clear();
    // The PE holds its query's k-th best distance: a point farther than it cannot enter the
    // list (equal ones still may, by index), so only closer ones go through the insert.
    float bound = job_->radius() ? 0.0f : slots_.bound(token.slot);
    for (std::uint32_t i = 0; i < count; ++i) {
      const float d = dist2(token.point, Point3{set[i].x, set[i].y, set[i].z});
      if (!job_->radius()) {
        if (local) keep_best({set[i].tag, d}, set[i]);
        if (d > bound) continue;
        if (slots_.insert(token.slot, {set[i].tag, d})) bound = slots_.bound(token.slot);
      } else if (d <= job_->r2) {
        hits.push_back({token.query, set[i].tag, d});
        if (local) local->push_back(set[i]);
      }
    }
    if (local && !job_->radius())
      for (const auto& b : best_) local->push_back(b.second);
  }

 private:
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
