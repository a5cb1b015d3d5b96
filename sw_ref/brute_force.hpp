// The test oracle: every query against every point, with the numeric contract and nothing else.
#pragma once

#include "cloud.hpp"
#include "results.hpp"
#include "search.hpp"

namespace tigris {

// Exact results for params.mode/k/radius/max_nn (approximation settings are ignored).
Results brute_force(const PointCloud& cloud, const PointCloud& queries, const SearchParams& params);

}  // namespace tigris
