#include "scoreboard.hpp"

#include <sstream>

namespace tigris {

void VisitRecorder::job_started(std::uint32_t num_queries) {
  out_ = SearchOutput{};
  out_.per_query.assign(num_queries, {});
}

void VisitRecorder::walked(std::uint32_t query, std::uint32_t top, std::uint32_t pruned) {
  QueryVisits& v = out_.per_query.at(query);
  v.top += top, v.pruned += pruned;
  out_.visits.top += top, out_.visits.pruned += pruned;
}

void VisitRecorder::leaf_scanned(std::uint32_t query, std::uint32_t leaf, std::uint32_t points) {
  QueryVisits& v = out_.per_query.at(query);
  v.leaf_points += points, ++v.leaf_visits;
  out_.visits.leaf_points += points, ++out_.visits.leaf_visits;
  out_.schedule.push_back({query, leaf});
}

namespace {

std::string describe(std::size_t q, const std::optional<std::string>& diff, const QueryVisits& g,
                     const QueryVisits& h, bool visits_ok) {
  std::ostringstream s;
  s << "query " << q << ":";
  if (diff) s << " results differ (golden vs accelerator: " << diff->substr(diff->find(':') + 2) << ")";
  if (!visits_ok)
    s << " visits differ (golden top/pruned/leaf points/leaf visits " << g.top << "/" << g.pruned << "/"
      << g.leaf_points << "/" << g.leaf_visits << ", accelerator " << h.top << "/" << h.pruned << "/"
      << h.leaf_points << "/" << h.leaf_visits << ")";
  return s.str();
}

}  // namespace

Verdict check_against_golden(const KdTree& tree, const PointCloud& queries, const SearchParams& params,
                             const SearchOutput& golden, const Results& hw_results,
                             const SearchOutput& hw_visits, std::size_t report_at_most) {
  Verdict v;
  const std::size_t nq = golden.results.num_queries();
  if (hw_results.num_queries() != nq || hw_visits.per_query.size() != nq) {
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
    const QueryVisits& h = hw_visits.per_query[q];
    const bool visits_ok = g.top == h.top && g.pruned == h.pruned && g.leaf_points == h.leaf_points &&
                           g.leaf_visits == h.leaf_visits;
    if (diff) ++v.result_mismatches;
    if (!visits_ok) ++v.visit_mismatches;
    if ((diff || !visits_ok) && v.first.size() < report_at_most) v.first.push_back(describe(q, diff, g, h, visits_ok));
  }
  // The accelerator's own leaf-visit order, replayed through the golden model, must give the
  // same answers: every visit it made is one the golden traversal expects, in a legal order.
  try {
    const SearchOutput replay = search(tree, queries, params, &hw_visits.schedule);
    if (const auto diff = first_difference(golden.results, replay.results))
      v.first.push_back("replaying the accelerator's schedule: " + *diff);
  } catch (const ScheduleError& e) {
    v.first.push_back(std::string("the accelerator's schedule does not replay: ") + e.what());
  }
  v.match = v.result_mismatches == 0 && v.visit_mismatches == 0 && v.first.empty();
  return v;
}

}  // namespace tigris
