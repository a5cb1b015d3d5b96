// The accelerator in the registration loop (docs/registration.md): what the search
// plug-in hands to the host side when it runs a stage's query set as one job, and what comes
// back. The pipeline knows nothing of the model; `tigris register --search accel` plugs in an
// implementation that simulates each job (testbench/accel_in_loop.hpp), and tests may plug in
// their own.
#pragma once

#include <cstdint>
#include <stdexcept>

#include "sw_ref/cloud.hpp"
#include "sw_ref/results.hpp"
#include "sw_ref/search.hpp"

namespace tigris::registration {

struct AccelJob {
  std::uint64_t tree_id = 0;           // the plug-in tree build it searches (a new id: a new tree image)
  const PointCloud* points = nullptr;  // the tree's points: its finite input points, in index order
  int top_height = 0;                  // the golden tree's top height (clamped to the cloud)
  const PointCloud* queries = nullptr;
  SearchParams params;  // exact, or approximate with its thresholds and leader settings
};

// Whether two jobs' searches ask the same (every field a search reads; the job's answer of one
// serves the other).
inline bool same_search(const SearchParams& a, const SearchParams& b) {
  return a.mode == b.mode && a.k == b.k && a.radius == b.radius && a.max_nn == b.max_nn &&
         a.approximate == b.approximate && a.approx_thd == b.approx_thd && a.leader_capacity == b.leader_capacity &&
         a.leader_width == b.leader_width && a.leader_scope == b.leader_scope &&
         a.leader_in_flight == b.leader_in_flight;
}

struct AccelAnswer {
  Results results;  // per query, indices into *points, in the golden model's canonical order
  std::uint64_t cycles = 0;
  double search_seconds = 0.0;  // cycles at the accelerator clock
  double host_seconds = 0.0;    // host link: tree image (when sent), queries, results
  double energy_pj = 0.0;
  VisitTotals visits;  // as the accelerator made them
};

// A job the accelerator did not answer correctly (a golden mismatch or a deadlock): the
// registration stops, the message names the job and the first differing query.
class AcceleratorFailure : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class AcceleratorPort {
 public:
  virtual ~AcceleratorPort() = default;
  // Runs one job. Throws AcceleratorFailure as above, std::invalid_argument when the job
  // cannot run (e.g. it does not fit the accelerator's buffers).
  virtual AccelAnswer run(const AccelJob& job) = 0;
  // A job that will be run() soon (the stage's next one, independent of the current): an
  // implementation may start it now, beside the jobs run() in between, and answer that run()
  // from it. It must not change any answer, and *job.points and *job.queries must keep their
  // contents until then. Ignoring it is always correct.
  virtual void prefetch(const AccelJob& /*job*/) {}
};

}  // namespace tigris::registration
