#include "stats.hpp"

#include <algorithm>
#include <cmath>

namespace tigris {

namespace {
// Nearest-rank percentile: the smallest value with at least p% of the values at or below it.
std::uint64_t percentile(const std::vector<std::uint64_t>& sorted, double p) {
  const auto rank = static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(sorted.size())));
  return sorted[std::max<std::size_t>(rank, 1) - 1];
}
}  // namespace

Distribution distribution(std::vector<std::uint64_t> values) {
  Distribution d;
  if (values.empty()) return d;
  std::sort(values.begin(), values.end());
  double sum = 0.0;
  for (std::uint64_t v : values) sum += static_cast<double>(v);
  d.mean = sum / static_cast<double>(values.size());
  d.p50 = percentile(values, 50.0);
  d.p99 = percentile(values, 99.0);
  d.max = values.back();
  return d;
}

}  // namespace tigris
