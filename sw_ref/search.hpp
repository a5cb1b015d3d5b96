// The golden model's searches (docs/model.md): exact NN, kNN and radius search on
// a KdTree, depth-first, with visit counts, and the approximate (leader/follower) search of the
// paper's Algorithm 1 (at a query's first leaf, as the authors' code; or at every leaf visit),
// driven by an optional schedule.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cloud.hpp"
#include "kdtree.hpp"
#include "leader_policy.hpp"
#include "results.hpp"
#include "schedule.hpp"

namespace tigris {

enum class Mode { NN, KNN, Radius };
Mode parse_mode(const std::string& name);  // "nn" | "knn" | "radius"
const char* to_string(Mode mode);

struct SearchParams {
  Mode mode = Mode::NN;
  int k = 1;                 // neighbours for kNN (NN: 1)
  float radius = 0.0f;       // metres, radius mode
  std::uint32_t max_nn = 0;  // radius: keep only the first max_nn (0: all); no effect on visits
  bool approximate = false;  // leader/follower search (Algorithm 1)
  float approx_thd = 0.0f;   // metres: a query within thd of a leader follows it
  LeaderScope leader_scope = LeaderScope::FirstLeaf;
  LeaderInFlight leader_in_flight = LeaderInFlight::Wait;  // first_leaf only
  int leader_capacity = 16;                                // leaders kept per leaf
  int leader_width = 0;         // every_leaf: R, a leader's local result list for NN/kNN (0: k)
  bool record_schedule = true;  // keep the (query, leaf) visit decisions

  int effective_k() const { return mode == Mode::NN ? 1 : k; }
  int effective_leader_width() const { return leader_width > 0 ? leader_width : effective_k(); }
};

// Paper defaults for the approximation threshold: 1.2 m for NN/kNN, 0.4 r for radius.
float default_approx_thd(const SearchParams& params);

// Throws std::invalid_argument naming the parameter: k < 1, r <= 0 or non-finite, thd < 0, ...
void validate(const SearchParams& params);

// One query's visit counts.
struct QueryVisits {
  std::uint32_t top = 0;              // top-tree nodes whose point was compared
  std::uint32_t pruned = 0;           // popped subtrees skipped by plane2 > bound
  std::uint32_t leaf_points = 0;      // leaf-set points compared (exact scans)
  std::uint32_t follower_points = 0;  // leader-list entries compared by a follower
  std::uint32_t leader_checks = 0;    // distances to a leaf's leaders
  std::uint32_t leaf_visits = 0;      // non-empty leaf sets reached
};

struct VisitTotals {
  std::uint64_t top = 0, pruned = 0, leaf_points = 0, follower_points = 0, leader_checks = 0, leaf_visits = 0;
  void add(const QueryVisits& v);
};

// The visit counters by name, in the one order every report lists them (stats.json,
// registration.json, the Python module): f(name, value) for a QueryVisits or a VisitTotals.
template <class Visits, class F>
void for_each_count(Visits&& v, F&& f) {  // a mutable v gives f its counters to set (a reader)
  f("top", v.top);
  f("pruned", v.pruned);
  f("leaf_points", v.leaf_points);
  f("follower_points", v.follower_points);
  f("leader_checks", v.leader_checks);
  f("leaf_visits", v.leaf_visits);
}
// The counters as a JSON object in that order, for any JSON type (nlohmann::ordered_json keeps
// the order in a file); sw_ref itself includes no JSON library.
template <class Json, class Visits>
Json visits_json(const Visits& v) {
  Json j = Json::object();
  for_each_count(v, [&](const char* name, std::uint64_t x) { j[name] = x; });
  return j;
}

// every_leaf counts leaf visits, first_leaf counts queries (a leader joins when it finishes).
struct LeaderTotals {
  std::uint64_t leaders = 0;             // queries (exact scans) that joined a Leader Buffer
  std::uint64_t followers = 0;           // queries (leaf visits) served from a leader's list
  std::uint64_t leader_buffer_full = 0;  // would-be leaders that found their leaf's buffer full
};

struct SearchOutput {
  Results results;
  std::vector<QueryVisits> per_query;
  VisitTotals visits;
  LeaderTotals leaders;
  Schedule schedule;  // the schedule used (recorded, or the replayed one)
};

// Thrown when a replayed schedule does not match the queries' own traversal.
class ScheduleError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Searches every query in `tree`. Without `replay`, queries run one at a time in index order;
// with it, leaf visits and (first_leaf) leaders' finishes happen in the schedule's order (each
// query's top-tree walk is its own, so only the leader state depends on the order) and every
// row must match the query's traversal exactly, else ScheduleError. A first_leaf leader without
// a finish row never joins (the accelerator may end a job before its record arrives).
// `progress(done, total)` is called now and then (queries, or schedule rows when replaying).
using Progress = std::function<void(std::size_t done, std::size_t total)>;
SearchOutput search(const KdTree& tree, const PointCloud& queries, const SearchParams& params,
                    const Schedule* replay = nullptr, const Progress& progress = {});

// One query at a time, in the caller's order, on one tree with fixed parameters: what a search
// library plug-in needs (registration). Approximate search keeps its leader state across
// calls, so a sequence of calls returns exactly what search() returns for the same queries in
// the same order.
class Searcher {
 public:
  Searcher(const KdTree& tree, const SearchParams& params);  // keeps a reference to `tree`
  ~Searcher();
  Searcher(const Searcher&) = delete;
  Searcher& operator=(const Searcher&) = delete;
  // Searches `q` (finite); `out` receives its neighbours in canonical order.
  void search(const Point3& q, std::vector<Neighbor>& out);
  const VisitTotals& visits() const;       // summed over every call
  const QueryVisits& last_visits() const;  // of the last call
  const LeaderTotals& leaders() const;
  std::uint64_t queries() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace tigris
