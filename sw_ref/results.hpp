// Search results in canonical order, per query, as one compressed array (queries in index
// order), plus the comparison the golden check uses and the results dump (docs/cli.md).
#pragma once

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "arith.hpp"

namespace tigris {

struct Results {
  std::vector<std::uint64_t> offset{0};  // query q's neighbours: [offset[q], offset[q+1])
  std::vector<Neighbor> neighbors;

  std::size_t num_queries() const { return offset.size() - 1; }
  std::size_t count(std::size_t q) const { return offset[q + 1] - offset[q]; }
  const Neighbor* begin(std::size_t q) const { return neighbors.data() + offset[q]; }
  const Neighbor* end(std::size_t q) const { return neighbors.data() + offset[q + 1]; }
  void append_query(const Neighbor* first, const Neighbor* last) {
    neighbors.insert(neighbors.end(), first, last);
    offset.push_back(neighbors.size());
  }
};

// Compares two result sets as lists (index and the bit pattern of dist2). Returns nothing when
// equal, else a description of the first differing query, e.g. for a golden-check report.
std::optional<std::string> first_difference(const Results& expected, const Results& actual);

// CSV `query,rank,index,dist2`, one row per neighbour, dist2 as %.9g (round-trips float32).
void write_results_csv(std::ostream& out, const Results& results);

}  // namespace tigris
