#include "scoreboard.hpp"

#include <sstream>

namespace tigris {

Verdict check_against_golden(const SearchOutput& golden, const Results& hw_results,
                             const std::vector<hw::QueryCounters>& hw_visits,
                             std::size_t report_at_most) {
  Verdict v;
  const std::size_t nq = golden.results.num_queries();
  if (hw_results.num_queries() != nq || hw_visits.size() != nq) {
    v.match = false;
    v.first.push_back("the accelerator returned " + std::to_string(hw_results.num_queries()) +
                      " queries, the golden model " + std::to_string(nq));
    return v;
  }
  for (std::size_t q = 0; q < nq; ++q) {
    Results one_g, one_h;  // compare this query alone, to reuse the canonical comparison
    one_g.append_query(golden.results.begin(q), golden.results.end(q));
    one_h.append_query(hw_results.begin(q), hw_results.end(q));
    const auto diff = first_difference(one_g, one_h);
    const QueryVisits& g = golden.per_query[q];
    const hw::QueryCounters& h = hw_visits[q];
    const bool visits_ok = g.top == h.top && g.pruned == h.pruned && g.leaf_points == h.leaf_points &&
                           g.leaf_visits == h.leaf_visits;
    if (diff) ++v.result_mismatches;
    if (!visits_ok) ++v.visit_mismatches;
    if ((diff || !visits_ok) && v.first.size() < report_at_most) {
      std::ostringstream s;
      s << "query " << q << ":";
      if (diff) s << " results differ (golden vs accelerator: " << diff->substr(diff->find(':') + 2) << ")";
      if (!visits_ok)
        s << " visits differ (golden top/pruned/leaf points/leaf visits " << g.top << "/" << g.pruned
          << "/" << g.leaf_points << "/" << g.leaf_visits << ", accelerator " << h.top << "/"
          << h.pruned << "/" << h.leaf_points << "/" << h.leaf_visits << ")";
      v.first.push_back(s.str());
    }
  }
  v.match = v.result_mismatches == 0 && v.visit_mismatches == 0;
  return v;
}

}  // namespace tigris
