// What the plug-in's searches cost (search_plugin.hpp): the counters of a pipeline stage, the
// work bound of a whole registration and the charging of one search to both. Apart from the
// plug-in because the pipeline and the command line read and report them (and set the budget)
// without searching, and the charging is the same for every point type.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <stdexcept>

#include "core/timer.hpp"
#include "sw_ref/search.hpp"

namespace tigris::registration {

// The work bound of a whole registration: every search adds the distances it
// computed (golden back-ends: top-tree nodes, leaf and follower points) and the neighbours it
// returned (all back-ends; FLANN counts only these). Above `limit` (0: none) the search throws
// WorkLimitExceeded, so an injected K of 100,000 or a 100 m shell stops with a message instead
// of running for minutes; `progress` is called about every 2 s of searching.
struct WorkBudget {
  double limit = 0.0;
  double spent = 0.0;
  std::uint64_t searches = 0;
  std::function<void(const WorkBudget&)> progress;
  std::chrono::steady_clock::time_point last_report = std::chrono::steady_clock::now();
};

class WorkLimitExceeded : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What one pipeline stage's searches cost. `searches` counts query points searched (PCL's
// batch calls loop over single ones), `builds` the trees built (one per input cloud set).
struct SearchCounters {
  std::uint64_t searches = 0, neighbors = 0, builds = 0;
  double search_seconds = 0.0, build_seconds = 0.0;
  VisitTotals visits;    // golden back-ends only
  LeaderTotals leaders;  // approximate only
  // With the accelerator in the loop: the jobs it ran and what they cost in the model, and the
  // searches it could not batch (answered by the golden model on the CPU, their seconds kept).
  // search_seconds then holds the jobs' simulation wall time too: not a CPU cost.
  struct Accelerated {
    std::uint64_t jobs = 0, queries = 0, cycles = 0, fallback_searches = 0;
    double modeled_search_seconds = 0.0, modeled_host_seconds = 0.0, energy_pj = 0.0;
    double fallback_seconds = 0.0;
    VisitTotals visits;  // the accelerator's
  } accel;
};

// Counts one search that began at `t0` and returned `n` neighbours into `counters`, its
// seconds less `excluded_seconds` (the time spent recording it, not the search's cost), and
// charges `budget` (null: none) its neighbours and the `distances` it computed. Throws
// WorkLimitExceeded when the budget's limit is passed; reports progress now and then.
void charge_search(SearchCounters& counters, WorkBudget* budget, int n, SteadyClock::time_point t0,
                   double excluded_seconds, double distances);

// Counts one golden search on the CPU: its visits, and the leaders and followers it made
// (`before` and `after`: its searcher's totals around it). Returns the distances it computed
// (top-tree nodes, leaf and follower points), its work for the budget.
double count_golden_search(SearchCounters& counters, const QueryVisits& visits, const LeaderTotals& before,
                           const LeaderTotals& after);

}  // namespace tigris::registration
