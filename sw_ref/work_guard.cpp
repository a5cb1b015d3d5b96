#include "work_guard.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

namespace tigris {

WorkEstimate estimate_work(const KdTree& tree, const PointCloud& queries, const SearchParams& params,
                           std::uint32_t sample) {
  WorkEstimate e;
  const std::size_t n = queries.size();
  if (n == 0 || sample == 0) return e;
  SearchParams exact = params;
  exact.approximate = false;
  exact.max_nn = 0;  // the hardware streams every hit before the host keeps max_nn of them
  Searcher searcher(tree, exact);
  std::vector<Neighbor> found;
  const std::size_t take = std::min<std::size_t>(n, sample);
  double visits = 0.0, hits = 0.0, leaf_visits = 0.0;
  for (std::size_t i = 0; i < take; ++i) {
    searcher.search(queries[i * n / take], found);  // evenly spread: frames are scan-ordered
    const QueryVisits& v = searcher.last_visits();
    visits += double(v.top) + double(v.leaf_points) + double(v.follower_points);
    hits += static_cast<double>(found.size());
    leaf_visits += double(v.leaf_visits);
  }
  e.sampled = take;
  e.visits_per_query = visits / static_cast<double>(take);
  e.hits_per_query = hits / static_cast<double>(take);
  e.leaf_visits_per_query = leaf_visits / static_cast<double>(take);
  e.visits = e.visits_per_query * static_cast<double>(n);
  e.hits = e.hits_per_query * static_cast<double>(n);
  return e;
}

void add_slot_traffic(WorkEstimate& e, std::size_t num_queries, std::uint64_t slot_bytes, int word_bytes) {
  const double words = std::ceil(static_cast<double>(slot_bytes) / std::max(word_bytes, 1));
  e.slot_words = static_cast<double>(num_queries) * (2.0 * e.leaf_visits_per_query + 1.0) * 2.0 * words;
}

namespace {
std::string sci(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", x);
  return b;
}
}  // namespace

void check_work(const WorkEstimate& e, const WorkLimits& limits, std::size_t num_queries) {
  const std::string sample =
      " (a sample of " + std::to_string(e.sampled) + " of the " + std::to_string(num_queries) + " queries: ";
  if (limits.max_work > 0 && e.slot_words > 0 && e.visits + e.slot_words > limits.max_work)
    throw std::invalid_argument(
        "the run would compute about " + sci(e.visits) + " distances and move about " + sci(e.slot_words) +
        " Result Buffer words through its k-wide result slots" + sample + sci(e.leaf_visits_per_query) +
        " leaf visits per query, each reading and writing the whole slot), above --max-work " + sci(limits.max_work) +
        "; use a smaller k (k beyond the cloud's points returns the whole cloud), or raise "
        "--max-work (0: no limit) if the run is meant to be that large");
  if (limits.max_work > 0 && e.visits > limits.max_work)
    throw std::invalid_argument(
        "the search would compute about " + sci(e.visits) + " node and point distances" + sample +
        sci(e.visits_per_query) + " per query), above --max-work " + sci(limits.max_work) +
        "; raise --max-work (0: no limit) if the run is meant to be that large, or make it smaller "
        "(fewer queries, a smaller radius or k, points that are not all alike)");
  if (limits.max_results > 0 && e.hits > limits.max_results)
    throw std::invalid_argument(
        "the search would return about " + sci(e.hits) + " neighbours" + sample + sci(e.hits_per_query) +
        " per query; 12 bytes each, held several times), above --max-results " + sci(limits.max_results) +
        "; raise --max-results (0: no limit) if there is memory for them, or use a smaller radius "
        "(--max-nn caps what is kept, not what the accelerator streams)");
}

}  // namespace tigris
