// Accuracy of approximate search (docs/model.md), measured against exact search of the
// same queries: NN/kNN by how often the result equals the exact one and by how much farther the
// returned neighbours are; radius by recall and precision of the returned sets.
#pragma once

#include <cstdint>

#include "results.hpp"
#include "search.hpp"

namespace tigris {

struct Accuracy {
  Mode mode = Mode::NN;
  std::uint64_t queries = 0;
  // NN/kNN.
  std::uint64_t exact_matches = 0;  // queries whose list equals the exact list (index and dist2)
  std::uint64_t ranks = 0;          // neighbour ranks compared (both lists hold that rank)
  std::uint64_t missing = 0;        // ranks the exact list holds and the approximate does not
  double mean_extra_m = 0.0;        // mean over ranks of sqrt(dist2) - sqrt(exact dist2), metres
  double max_extra_m = 0.0;
  // Radius (pooled over all queries).
  std::uint64_t exact_hits = 0, returned_hits = 0, true_hits = 0;

  double exact_match_fraction() const { return queries ? static_cast<double>(exact_matches) / queries : 1.0; }
  double recall() const { return exact_hits ? static_cast<double>(true_hits) / exact_hits : 1.0; }
  double precision() const { return returned_hits ? static_cast<double>(true_hits) / returned_hits : 1.0; }
};

// Compares `approx` with `exact` (same queries, canonical order per query).
Accuracy measure_accuracy(Mode mode, const Results& exact, const Results& approx);

}  // namespace tigris
