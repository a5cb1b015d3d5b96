#include "search_counters.hpp"

#include <cstdio>

namespace tigris::registration {

void charge_search(SearchCounters& counters, WorkBudget* budget, int n, SteadyClock::time_point t0,
                   double excluded_seconds, double distances) {
  ++counters.searches;
  counters.neighbors += static_cast<std::uint64_t>(n > 0 ? n : 0);
  counters.search_seconds += seconds_since(t0) - excluded_seconds;
  if (!budget) return;
  budget->spent += static_cast<double>(n > 0 ? n : 0) + distances;
  if (++budget->searches % 4096 == 0 && budget->progress &&
      SteadyClock::now() - budget->last_report >= std::chrono::seconds(2)) {
    budget->last_report = SteadyClock::now();
    budget->progress(*budget);
  }
  if (budget->limit > 0.0 && budget->spent > budget->limit) {
    char msg[320];
    std::snprintf(msg, sizeof msg,
                  "the registration's KD-tree searches have computed and returned more than %.3g "
                  "distances and neighbours (%llu searches), above --max-work %.3g",
                  budget->spent, static_cast<unsigned long long>(budget->searches), budget->limit);
    throw WorkLimitExceeded(msg);
  }
}

double count_golden_search(SearchCounters& counters, const QueryVisits& visits, const LeaderTotals& before,
                           const LeaderTotals& after) {
  counters.visits.add(visits);
  counters.leaders.leaders += after.leaders - before.leaders;
  counters.leaders.followers += after.followers - before.followers;
  counters.leaders.leader_buffer_full += after.leader_buffer_full - before.leader_buffer_full;
  return static_cast<double>(visits.top + visits.leaf_points + visits.follower_points);
}

}  // namespace tigris::registration
