// The leaf-visit schedule (docs/model.md, approximate search): the sequence of (query, leaf) visit
// decisions. A dependency-free vocabulary header: the golden model replays schedules, the
// testbench records the accelerator's, and schedule_csv.* reads and writes them.
#pragma once

#include <cstdint>
#include <vector>

namespace tigris {

// One leaf visit decision: query `query` scans leaf `leaf` (non-empty leaves only).
struct ScheduleEntry {
  std::uint32_t query = 0;
  std::uint32_t leaf = 0;
  bool operator==(const ScheduleEntry& o) const { return query == o.query && leaf == o.leaf; }
};
using Schedule = std::vector<ScheduleEntry>;

}  // namespace tigris
