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
  // One PE scans leaf set `token.leaf` for its query: NN/kNN results go to its Result Buffer
  // slot, radius hits to `hits`. Returns the points compared.
  std::uint32_t scan(const QueryToken& token, std::vector<tlm_if::ResultRecord>& hits) {
    const std::uint32_t first = tree_.leaf_begin(token.leaf), last = tree_.leaf_end(token.leaf);
    const tlm_if::PointEntry* set = tree_.leaf_entries();
    for (std::uint32_t i = first; i < last; ++i) {
      const float d = dist2(token.point, Point3{set[i].x, set[i].y, set[i].z});
      if (!job_->radius())
        slots_.insert(token.slot, {set[i].tag, d});
      else if (d <= job_->r2)
        hits.push_back({token.query, set[i].tag, d});
    }
    return last - first;
  }

 private:
  const JobDescriptor* job_ = nullptr;
  TreeView tree_;
  ResultSlots slots_;
};

}  // namespace tigris::hw
