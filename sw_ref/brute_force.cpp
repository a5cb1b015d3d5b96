#include "brute_force.hpp"

#include <algorithm>

namespace tigris {

Results brute_force(const PointCloud& cloud, const PointCloud& queries, const SearchParams& params) {
  validate(params);
  Results out;
  std::vector<Neighbor> all;
  const float r2 = square(params.radius);
  for (const Point3& q : queries) {
    all.clear();
    for (std::uint32_t i = 0; i < cloud.size(); ++i) {
      const float d = dist2(q, cloud[i]);
      if (params.mode != Mode::Radius || d <= r2) all.push_back({i, d});
    }
    std::size_t keep = all.size();
    if (params.mode != Mode::Radius)
      keep = std::min<std::size_t>(keep, static_cast<std::size_t>(params.effective_k()));
    else if (params.max_nn > 0)
      keep = std::min<std::size_t>(keep, params.max_nn);
    std::partial_sort(all.begin(), all.begin() + keep, all.end(), Closer{});
    out.append_query(all.data(), all.data() + keep);
  }
  return out;
}

}  // namespace tigris
