// The golden check, written once: the scoreboard observes the accelerator (per-query visit
// counts, leader decisions and the leaf-visit schedule in simulated-time order) and compares
// every query's results (index and dist2 bits, canonical order) and visit counts (top, pruned,
// leaf points, follower points, leader checks, leaf visits) and the leader / follower /
// leader-buffer-full totals with the golden model. The golden model runs the queries in index
// order; under approximate search the leader state depends on the order of leaf visits, so the
// golden side then is the replay of the accelerator's schedule through sw_ref (which also
// checks that every recorded visit is one the query's own traversal makes).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "hw/host/scan_service.hpp"
#include "hw/observer.hpp"
#include "sw_ref/search.hpp"

namespace tigris {

// Records what the accelerator reports, in the golden model's shape.
// It also takes the host's prefetch hints (hw/host/scan_service.hpp): its per-query records are
// megabytes touched at random.
class VisitRecorder final : public hw::JobObserver, public hw::QueryHint {
 public:
  void job_started(std::uint32_t num_queries) override;
  void soon(std::uint32_t query) override { __builtin_prefetch(out_.per_query.data() + query, 1); }
  void walked(std::uint32_t query, std::uint32_t top, std::uint32_t pruned) override;
  void leaf_scanned(std::uint32_t query, std::uint32_t leaf, const hw::LeafVisit& visit) override;
  void leader_finished(std::uint32_t query, std::uint32_t leaf, bool joined) override;
  void follower_served(std::uint32_t query, std::uint32_t points) override;
  // Per-query counts, their totals and the schedule (results left empty).
  const SearchOutput& visits() const { return out_; }
  SearchOutput take_visits() { return std::move(out_); }  // after the run

 private:
  SearchOutput out_;
};

// The golden model's search (sw_ref search()), exact search on two host threads, half of the
// queries each (its queries do not depend on each other); approximate search as one. The same
// output either way (tests check). `replay`: the schedule to replay (see search()).
SearchOutput golden_search(const KdTree& tree, const PointCloud& queries, const SearchParams& params,
                           const Schedule* replay = nullptr);

struct Verdict {
  bool match = true;
  std::uint64_t result_mismatches = 0, visit_mismatches = 0;
  std::vector<std::string> first;  // descriptions of the first mismatching queries
};

// Compares the accelerator's results and recorded visits with `golden` (the golden model's
// search of `queries` in `tree` with `params`), then replays the recorded schedule through the
// golden model: every visit must be one its traversal expects and the results must not change.
// `ids` names the queries in the descriptions when they are a sample of a job's (sampled
// simulation: query i is the job's query ids[i]).
Verdict check_against_golden(const KdTree& tree, const PointCloud& queries, const SearchParams& params,
                             const SearchOutput& golden, const Results& hw_results, const SearchOutput& hw_visits,
                             std::size_t report_at_most = 5, const std::vector<std::uint32_t>* ids = nullptr);

}  // namespace tigris
