// The leaf-visit schedule (docs/model.md, approximate search): the sequence of (query, leaf) visit
// decisions and leaders' finishes. A dependency-free vocabulary header: the golden model replays schedules, the
// testbench records the accelerator's, and schedule_csv.* reads and writes them.
#pragma once

#include <cstdint>
#include <vector>

namespace tigris {

// One decision: query `query` visits leaf `leaf` (non-empty leaves only), or (approximate
// search, first_leaf) query `query`, a leader of its first leaf `leaf`, has finished its search
// and its record reached the leaf's Leader Buffer.
struct ScheduleEntry {
  enum class Event : std::uint8_t { Visit, Finish };
  std::uint32_t query = 0;
  std::uint32_t leaf = 0;
  Event event = Event::Visit;
  bool operator==(const ScheduleEntry& o) const { return query == o.query && leaf == o.leaf && event == o.event; }
};
using Schedule = std::vector<ScheduleEntry>;

}  // namespace tigris
