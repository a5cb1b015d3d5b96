// Summary statistics for per-query counts (the heavy tail of cross-frame NN matters).
#pragma once

#include <cstdint>
#include <vector>

namespace tigris {

struct Distribution {
  double mean = 0.0;
  std::uint64_t p50 = 0, p99 = 0, max = 0;  // nearest-rank percentiles
};

Distribution distribution(std::vector<std::uint64_t> values);

}  // namespace tigris
