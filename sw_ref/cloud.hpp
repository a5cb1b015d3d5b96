// Point clouds as the golden model sees them: float32 x, y, z indexed 0..N-1 in input order.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "arith.hpp"
#include "core/input_error.hpp"  // the cloud checks throw InputError

namespace tigris {

using PointCloud = std::vector<Point3>;

// The largest coordinate magnitude accepted. dist2 sums three squared float32 differences:
// with |coordinates| <= 1e18 a difference is at most 2e18 and the sum 1.2e37, inside float32's
// 3.4e38, so no distance overflows to infinity (which would make every point "nearest" or
// every point "within r" while both models agree).
constexpr float kMaxCoordinate = 1e18f;

// Policy (docs/model.md, decisions): a cloud with a NaN/Inf coordinate, a coordinate beyond
// kMaxCoordinate, or no point is rejected, never silently repaired. `label` names the source in
// the message (usually the file path).
void validate_cloud(const PointCloud& cloud, const std::string& label);

}  // namespace tigris
