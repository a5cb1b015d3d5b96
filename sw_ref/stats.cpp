#include "stats.hpp"

#include <algorithm>
#include <cmath>

namespace tigris {

namespace {
// Nearest-rank percentile: the smallest value with at least p% of the values at or below it.
// Selection, not a sort: a full frame has 10^5 latencies and this runs inside the timed run.
std::uint64_t percentile(std::vector<std::uint64_t>& values, double p) {
  const auto rank = static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(values.size())));
  const auto nth = values.begin() + static_cast<std::ptrdiff_t>(std::max<std::size_t>(rank, 1) - 1);
  std::nth_element(values.begin(), nth, values.end());
  return *nth;
}
}  // namespace

Distribution distribution(std::vector<std::uint64_t> values) {
  Distribution d;
  if (values.empty()) return d;
  double sum = 0.0;
  for (std::uint64_t v : values) sum += static_cast<double>(v);
  d.mean = sum / static_cast<double>(values.size());
  d.p50 = percentile(values, 50.0);
  d.p99 = percentile(values, 99.0);
  d.max = *std::max_element(values.begin(), values.end());
  return d;
}

}  // namespace tigris
