#include "accuracy.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace tigris {

namespace {

bool same(const Neighbor& a, const Neighbor& b) {
  return a.index == b.index && std::memcmp(&a.dist2, &b.dist2, sizeof(float)) == 0;
}

}  // namespace

Accuracy measure_accuracy(Mode mode, const Results& exact, const Results& approx) {
  if (exact.num_queries() != approx.num_queries())
    throw std::invalid_argument("accuracy: the exact and approximate results differ in queries");
  Accuracy a;
  a.mode = mode;
  a.queries = exact.num_queries();
  double extra_sum = 0.0;
  std::vector<std::uint32_t> e_idx, a_idx;
  for (std::size_t q = 0; q < a.queries; ++q) {
    const Neighbor *e = exact.begin(q), *p = approx.begin(q);
    const std::size_t ne = exact.count(q), na = approx.count(q);
    if (mode != Mode::Radius) {
      a.exact_matches += ne == na && std::equal(e, e + ne, p, same);
      const std::size_t n = std::min(ne, na);
      for (std::size_t i = 0; i < n; ++i) {
        const double extra = std::sqrt(static_cast<double>(p[i].dist2)) - std::sqrt(static_cast<double>(e[i].dist2));
        extra_sum += extra;
        a.max_extra_m = std::max(a.max_extra_m, extra);
      }
      a.ranks += n;
      a.missing += ne > na ? ne - na : 0;
    } else {
      e_idx.clear(), a_idx.clear();
      for (std::size_t i = 0; i < ne; ++i) e_idx.push_back(e[i].index);
      for (std::size_t i = 0; i < na; ++i) a_idx.push_back(p[i].index);
      std::sort(e_idx.begin(), e_idx.end());
      std::sort(a_idx.begin(), a_idx.end());
      std::size_t common = 0;
      for (std::size_t i = 0, j = 0; i < e_idx.size() && j < a_idx.size();) {
        if (e_idx[i] == a_idx[j])
          ++common, ++i, ++j;
        else if (e_idx[i] < a_idx[j])
          ++i;
        else
          ++j;
      }
      a.exact_matches += ne == na && common == ne;
      a.exact_hits += ne, a.returned_hits += na, a.true_hits += common;
    }
  }
  a.mean_extra_m = a.ranks ? extra_sum / static_cast<double>(a.ranks) : 0.0;
  return a;
}

}  // namespace tigris
