// The Search Unit's 1-D systolic PE array (paper section 5.3, Fig. 9): query-stationary, the
// Node Set streams through; each PE's three-stage pipeline (read, distance, insert) never stalls.
#pragma once

#include <cstdint>
#include <vector>

#include "hw/job.hpp"
#include "hw/mem/result_slots.hpp"

namespace tigris::hw {

class PeArray {
 public:
  // Cycles to stream `points` entries past `queries` occupied PEs: the last point enters at
  // points - 1, reaches the last PE queries - 1 later, and leaves its pipeline after `depth`.
  static std::uint64_t stream_cycles(std::uint64_t points, std::uint64_t queries, int depth) {
    return points == 0 || queries == 0 ? 0 : points + queries - 1 + static_cast<std::uint64_t>(depth);
  }

  // One PE scans leaf set `leaf` for the query of `token`: NN/kNN results go to its Result
  // Buffer slot, radius hits to `hits`. Returns the points compared.
  static std::uint32_t scan(Job& job, const QueryToken& token,
                            std::vector<tlm_if::ResultRecord>& hits) {
    const std::uint32_t first = job.leaf_dir[token.leaf], last = job.leaf_dir[token.leaf + 1];
    const tlm_if::PointEntry* set = job.entries + job.num_top_nodes;
    const Point3 q = job.query(token.query);
    if (job.mode == tlm_if::SearchMode::Radius) {
      for (std::uint32_t i = first; i < last; ++i) {
        const float d = dist2(q, Point3{set[i].x, set[i].y, set[i].z});
        if (d <= job.r2) hits.push_back({token.query, set[i].tag, d});
      }
    } else {
      ResultSlots slots(job.result_slots, job.k);
      for (std::uint32_t i = first; i < last; ++i)
        slots.insert(token.slot, set[i].tag, dist2(q, Point3{set[i].x, set[i].y, set[i].z}));
    }
    QueryCounters& c = job.counters[token.query];
    c.leaf_points += last - first;
    ++c.leaf_visits;
    return last - first;
  }
};

}  // namespace tigris::hw
