// The accelerator in the loop, on the plug-in's side (search_plugin.hpp): the pipeline
// announces the points of the searches about to come, in the order PCL will make them. The
// first search of the first announced point runs them all as one accelerator job with that
// search's parameters; the calls that follow are served from the job's results while each asks
// for the next announced point with the same parameters. A set runs once: a stage that
// searches the same points again announces them again. Any other search is answered by the
// golden model on the CPU and counted as a fallback. Announcements may queue up: the next one
// is made when the current set is used up.
//
// Apart from the plug-in because none of it depends on PCL's point type: the template hands
// over the announced points (the finite ones) and each search as a golden-model query.
#pragma once

#include <cstddef>
#include <deque>
#include <functional>
#include <optional>
#include <vector>

#include <pcl/types.h>

#include "accelerator_port.hpp"
#include "golden_tree.hpp"
#include "search_counters.hpp"
#include "sw_ref/cloud.hpp"
#include "sw_ref/search.hpp"

namespace tigris::registration {

// One query's neighbours in a job's results: indices into the tree's points.
struct JobNeighbors {
  const Neighbor* first = nullptr;
  const Neighbor* last = nullptr;
};

class AnnouncedJobs {
 public:
  // The next searches are of `queries` (finite points), in this order: a new job.
  void announce(PointCloud queries);
  // Queues `announce`, to be called (and to call announce()) when the current set is used up.
  void then(std::function<void()> announce) { pending_.push_back(std::move(announce)); }
  // The tree was rebuilt: the announced set is searched (its job run) on the new tree.
  void rebuilt() {
    ran_ = false;
    cursor_ = 0;
  }

  // Before each search: makes the queued announcement when the current set's job ran and every
  // point of it was served.
  void announce_next();
  // Serves a search of `q` with `p` from the announced set's job, running the job on `tree`
  // through `port` first (counted into `counters`) when `q` is the set's first point; nothing
  // when the search is not the next announced one. Throws AcceleratorFailure when the job's
  // answer does not cover its queries.
  std::optional<JobNeighbors> serve(const SearchParams& p, const Point3& q, const GoldenTree& tree,
                                    AcceleratorPort& port, SearchCounters::Accelerated& counters);

  // Hands the announced set's job, as serve() would run it with `p` on `tree`, to `port` to
  // start now (AcceleratorPort::prefetch); nothing when there is no set or its job ran.
  void prefetch(const SearchParams& p, const GoldenTree& tree, AcceleratorPort& port) const;

  // The input indices (`map`: a tree point's index in the input cloud) of every neighbour the
  // last job returned, sorted, each once.
  pcl::Indices last_job_neighbors(const std::vector<pcl::index_t>& map) const;

 private:
  PointCloud expected_;                        // the announced queries
  std::deque<std::function<void()>> pending_;  // the announcements after it
  AccelAnswer answer_;                         // the last job's
  SearchParams params_;                        // the last job's
  bool ran_ = false;                           // the announced set's job ran
  std::size_t cursor_ = 0;                     // the next announced query to serve
};

}  // namespace tigris::registration
