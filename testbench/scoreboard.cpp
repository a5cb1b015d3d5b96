#include "scoreboard.hpp"

#include <cstring>
#include <exception>
#include <optional>
#include <sstream>
#include <thread>

namespace tigris {

void VisitRecorder::job_started(std::uint32_t num_queries) {
  out_ = SearchOutput{};
  out_.per_query.assign(num_queries, {});
  // Room for a typical job's leaf visits at once (a few per query): growing by doubling would
  // copy the schedule and touch its pages twice; pages reserved and not written cost nothing.
  out_.schedule.reserve(std::size_t{8} * num_queries);
}

void VisitRecorder::walked(std::uint32_t query, std::uint32_t top, std::uint32_t pruned) {
  QueryVisits& v = out_.per_query.at(query);
  v.top += top, v.pruned += pruned;
  out_.visits.top += top, out_.visits.pruned += pruned;
}

void VisitRecorder::leaf_scanned(std::uint32_t query, std::uint32_t leaf, const hw::LeafVisit& visit) {
  QueryVisits one;
  one.leaf_points = visit.leaf_points;
  one.follower_points = visit.follower_points;
  one.leader_checks = visit.leader_checks;
  one.leaf_visits = 1;
  QueryVisits& v = out_.per_query.at(query);
  v.leaf_points += one.leaf_points, v.follower_points += one.follower_points;
  v.leader_checks += one.leader_checks, ++v.leaf_visits;
  out_.visits.add(one);
  using Kind = hw::LeafVisit::Kind;
  out_.leaders.leaders += visit.kind == Kind::Leader;
  out_.leaders.followers += visit.kind == Kind::Follower;
  out_.leaders.leader_buffer_full += visit.kind == Kind::LeaderBufferFull;
  out_.schedule.push_back({query, leaf});
}

void VisitRecorder::follower_served(std::uint32_t query, std::uint32_t points) {
  out_.per_query.at(query).follower_points += points;
  out_.visits.follower_points += points;
}

void VisitRecorder::leader_finished(std::uint32_t query, std::uint32_t leaf, bool joined) {
  out_.leaders.leaders += joined;
  out_.leaders.leader_buffer_full += !joined;
  out_.schedule.push_back({query, leaf, ScheduleEntry::Event::Finish});
}

namespace {

bool same_visits(const QueryVisits& a, const QueryVisits& b) {
  return a.top == b.top && a.pruned == b.pruned && a.leaf_points == b.leaf_points &&
         a.follower_points == b.follower_points && a.leader_checks == b.leader_checks && a.leaf_visits == b.leaf_visits;
}

std::string counts(const QueryVisits& v) {
  std::ostringstream s;
  s << v.top << "/" << v.pruned << "/" << v.leaf_points << "/" << v.follower_points << "/" << v.leader_checks << "/"
    << v.leaf_visits;
  return s.str();
}

std::string describe(std::size_t q, const std::optional<std::string>& diff, const QueryVisits& g, const QueryVisits& h,
                     bool visits_ok) {
  std::ostringstream s;
  s << "query " << q << ":";
  if (diff) s << " results differ (golden vs accelerator: " << diff->substr(diff->find(':') + 2) << ")";
  if (!visits_ok)
    s << " visits differ (top/pruned/leaf points/follower points/leader checks/leaf visits: golden " << counts(g)
      << ", accelerator " << counts(h) << ")";
  return s.str();
}

// Query q's lists, index and dist2 bit pattern (as first_difference compares them).
bool same_results(const Results& a, const Results& b, std::size_t q) {
  if (a.count(q) != b.count(q)) return false;
  for (const Neighbor *x = a.begin(q), *y = b.begin(q); x != a.end(q); ++x, ++y)
    if (x->index != y->index || std::memcmp(&x->dist2, &y->dist2, sizeof x->dist2) != 0) return false;
  return true;
}

std::string totals(const LeaderTotals& t) {
  return std::to_string(t.leaders) + "/" + std::to_string(t.followers) + "/" + std::to_string(t.leader_buffer_full);
}

// Exact search: a query's traversal depends on that query alone, so the one leaf order a replay
// accepts for it is the in-order golden run's. Comparing the accelerator's schedule with that,
// query by query, is the replay without a second golden run: the same rows fail with the same
// words (run_replay in sw_ref/search.cpp), and a schedule that passes replays to the golden
// results. Empty when it replays; nullopt when `golden` has no schedule for every query (a
// sampled job's golden figures): replay then.
std::optional<std::string> exact_schedule_error(const SearchOutput& golden_run, const Schedule& hw, std::size_t nq) {
  constexpr std::uint32_t kDone = ~0u;
  const Schedule& golden = golden_run.schedule;
  if (golden_run.per_query.size() != nq) return std::nullopt;
  std::vector<std::uint64_t> at(nq + 1, 0);  // each query's golden leaves: golden[at[q] .. at[q + 1])
  for (const ScheduleEntry& e : golden) {
    if (e.query >= nq || e.event != ScheduleEntry::Event::Visit) return std::nullopt;
    ++at[e.query + 1];
  }
  for (std::size_t q = 0; q < nq; ++q)
    if (at[q + 1] != golden_run.per_query[q].leaf_visits) return std::nullopt;  // not every visit recorded
  for (std::size_t q = 0; q < nq; ++q) at[q + 1] += at[q];
  std::vector<std::uint32_t> leaves(golden.size());
  {
    std::vector<std::uint64_t> fill(at.begin(), at.end() - 1);
    for (const ScheduleEntry& e : golden) leaves[fill[e.query]++] = e.leaf;
  }
  std::vector<std::uint64_t> next(at.begin(), at.end() - 1);
  const auto pending = [&](std::uint32_t q) { return next[q] < at[q + 1] ? leaves[next[q]] : kDone; };
  for (std::size_t s = 0; s < hw.size(); ++s) {
    const ScheduleEntry& e = hw[s];
    const auto row = [&] {  // built only for an error
      return "schedule row " + std::to_string(s) + " (query " + std::to_string(e.query) + ", leaf " +
             std::to_string(e.leaf) + "): ";
    };
    if (e.query >= nq) return row() + "there are only " + std::to_string(nq) + " queries";
    if (e.event == ScheduleEntry::Event::Finish)
      return row() +
             "a leader's finish row belongs to approximate search with leader scope first_leaf and in-flight policy "
             "finished_only";
    const std::uint32_t want = pending(e.query);
    if (want == kDone) return row() + "the query has already finished its search";
    if (want != e.leaf) return row() + "the query's next leaf visit is leaf " + std::to_string(want);
    ++next[e.query];
  }
  for (std::uint32_t q = 0; q < nq; ++q)
    if (pending(q) != kDone)
      return "the schedule ends but query " + std::to_string(q) + " still has to visit leaf " +
             std::to_string(pending(q));
  return std::string();
}

}  // namespace

SearchOutput golden_search(const KdTree& tree, const PointCloud& queries, const SearchParams& params,
                           const Schedule* replay) {
  const std::size_t half = queries.size() / 2;
  if (params.approximate || half < 1024) return search(tree, queries, params, replay);
  const PointCloud first(queries.begin(), queries.begin() + static_cast<std::ptrdiff_t>(half));
  const PointCloud second(queries.begin() + static_cast<std::ptrdiff_t>(half), queries.end());
  Schedule rows[2];
  if (replay)
    for (ScheduleEntry e : *replay) {
      const bool later = e.query >= half;
      if (later) e.query -= static_cast<std::uint32_t>(half);
      rows[later].push_back(e);
    }
  SearchOutput a, b;
  std::exception_ptr failure;
  std::thread other([&] {
    try {
      a = search(tree, first, params, replay ? &rows[0] : nullptr);
    } catch (...) {
      failure = std::current_exception();
    }
  });
  try {
    b = search(tree, second, params, replay ? &rows[1] : nullptr);
  } catch (...) {
    other.join();
    return search(tree, queries, params, replay);  // throws again, naming the job's own row and query
  }
  other.join();
  if (failure) return search(tree, queries, params, replay);
  for (std::size_t q = 0; q < second.size(); ++q) a.results.append_query(b.results.begin(q), b.results.end(q));
  a.per_query.insert(a.per_query.end(), b.per_query.begin(), b.per_query.end());
  for (const QueryVisits& v : b.per_query) a.visits.add(v);
  a.leaders.leaders += b.leaders.leaders, a.leaders.followers += b.leaders.followers;
  a.leaders.leader_buffer_full += b.leaders.leader_buffer_full;
  if (replay) {
    a.schedule = *replay;
  } else {  // in query order, as one search records it
    for (ScheduleEntry e : b.schedule) {
      e.query += static_cast<std::uint32_t>(half);
      a.schedule.push_back(e);
    }
  }
  return a;
}

Verdict check_against_golden(const KdTree& tree, const PointCloud& queries, const SearchParams& params,
                             const SearchOutput& golden, const Results& hw_results, const SearchOutput& hw_visits,
                             std::size_t report_at_most, const std::vector<std::uint32_t>* ids) {
  Verdict v;
  const std::size_t nq = queries.size();
  if (hw_results.num_queries() != nq || hw_visits.per_query.size() != nq) {
    v.match = false;
    v.first.push_back("the accelerator returned " + std::to_string(hw_results.num_queries()) +
                      " queries, the golden model " + std::to_string(nq));
    return v;
  }
  // The accelerator's own leaf-visit order, replayed through the golden model: every visit it
  // made must be one the query's traversal expects, in a legal order.
  const auto no_replay = [&](const std::string& why) {
    v.match = false;
    v.first.push_back("the accelerator's schedule does not replay: " + why);
    return v;
  };
  SearchOutput replay;
  const std::optional<std::string> exact_error =
      params.approximate ? std::nullopt : exact_schedule_error(golden, hw_visits.schedule, nq);
  if (exact_error) {
    if (!exact_error->empty()) return no_replay(*exact_error);
  } else {
    try {
      replay = golden_search(tree, queries, params, &hw_visits.schedule);
    } catch (const ScheduleError& e) {
      return no_replay(e.what());
    }
  }
  // Exact search does not depend on the order: the replay must agree with the in-order golden
  // run, which is the reference (a schedule the in-order run gives replays to its results, by
  // the argument at exact_schedule_error). Approximate search does: the replay is the reference.
  const SearchOutput& ref = params.approximate ? replay : golden;
  if (!params.approximate && !exact_error)
    if (const auto diff = first_difference(golden.results, replay.results))
      v.first.push_back("replaying the accelerator's schedule: " + *diff);
  for (std::size_t q = 0; q < nq; ++q) {
    std::optional<std::string> diff;
    if (!same_results(ref.results, hw_results, q)) {
      Results one_g, one_h;  // this query alone, described by the canonical comparison
      one_g.append_query(ref.results.begin(q), ref.results.end(q));
      one_h.append_query(hw_results.begin(q), hw_results.end(q));
      diff = first_difference(one_g, one_h);
      if (!diff) diff = "results differ";  // not expected: first_difference compares the same
    }
    const bool visits_ok = same_visits(ref.per_query[q], hw_visits.per_query[q]);
    if (diff) ++v.result_mismatches;
    if (!visits_ok) ++v.visit_mismatches;
    if ((diff || !visits_ok) && v.first.size() < report_at_most)
      v.first.push_back(describe(ids ? (*ids)[q] : q, diff, ref.per_query[q], hw_visits.per_query[q], visits_ok));
  }
  const LeaderTotals& g = ref.leaders;
  const LeaderTotals& h = hw_visits.leaders;
  if (g.leaders != h.leaders || g.followers != h.followers || g.leader_buffer_full != h.leader_buffer_full)
    v.first.push_back("leaders/followers/leader-buffer-full differ: golden " + totals(g) + ", accelerator " +
                      totals(h));
  v.match = v.result_mismatches == 0 && v.visit_mismatches == 0 && v.first.empty();
  return v;
}

}  // namespace tigris
