// The golden check: every query's results (index and dist2 bits, canonical order) and visit
// counts (top, pruned, leaf points, leaf visits) from the accelerator against the golden model.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hw/job.hpp"
#include "sw_ref/search.hpp"

namespace tigris {

struct Verdict {
  bool match = true;
  std::uint64_t result_mismatches = 0, visit_mismatches = 0;
  std::vector<std::string> first;  // descriptions of the first mismatching queries
};

Verdict check_against_golden(const SearchOutput& golden, const Results& hw_results,
                             const std::vector<hw::QueryCounters>& hw_visits,
                             std::size_t report_at_most = 5);

}  // namespace tigris
