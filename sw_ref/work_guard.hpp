// The work and memory guard: before the search starts, a sample of the queries is
// searched by the golden model and the whole run's node and point visits and result records
// are extrapolated from it. A run estimated above --max-work visits or --max-results records
// stops with exit 2 and says how to raise the limit, instead of running for hours or dying of
// std::bad_alloc (50,000 identical points defeat every prune; a 100 m radius returns the cloud).
#pragma once

#include <cstdint>
#include <string>

#include "sw_ref/cloud.hpp"
#include "sw_ref/kdtree.hpp"
#include "sw_ref/search.hpp"

namespace tigris {

struct WorkLimits {
  double max_work = 2e9;     // node + point distance computations, summed over the queries; 0: none
  double max_results = 2e8;  // result records (12 bytes each, held several times); 0: none
};

struct WorkEstimate {
  std::uint64_t sampled = 0;        // queries searched for the estimate
  double visits_per_query = 0.0;    // top-tree nodes + leaf points + leader-list entries
  double hits_per_query = 0.0;      // neighbours found (radius: before --max-nn, as the stream is)
  double visits = 0.0, hits = 0.0;  // extrapolated to every query
  double leaf_visits_per_query = 0.0;
  // tigris run, NN/kNN: the Result Buffer words its result slots move. An RU walk and an SU
  // batch each read and write a query's whole k-wide slot, and the model books every word, so a
  // k far beyond the cloud (k = 100,000 on 2,000 points) costs minutes though the distances
  // are few. Set by add_slot_traffic; counts against --max-work with the distances.
  double slot_words = 0.0;
};

// Searches up to `sample` queries spread evenly over `queries` (exact search, one at a time).
WorkEstimate estimate_work(const KdTree& tree, const PointCloud& queries, const SearchParams& params,
                           std::uint32_t sample = 128);

// Adds the slot traffic of a run with slots of `slot_bytes` in words of `word_bytes`: per query,
// one RU walk per leaf visit plus the last, one SU batch per leaf visit, each a read and a write.
void add_slot_traffic(WorkEstimate& estimate, std::size_t num_queries, std::uint64_t slot_bytes, int word_bytes);

// Throws std::invalid_argument naming the limit when the estimate exceeds it.
void check_work(const WorkEstimate& estimate, const WorkLimits& limits, std::size_t num_queries);

}  // namespace tigris
