#include "cloud.hpp"

#include <cmath>
#include <sstream>

namespace tigris {

void validate_cloud(const PointCloud& cloud, const std::string& label) {
  if (cloud.empty()) throw InputError(label + ": the point cloud is empty");
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Point3& p = cloud[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      std::ostringstream msg;
      msg << label << ": point " << i << " has a non-finite coordinate (" << p.x << ", " << p.y << ", " << p.z
          << "); NaN/Inf points are rejected, filter them out first";
      throw InputError(msg.str());
    }
    if (std::fabs(p.x) > kMaxCoordinate || std::fabs(p.y) > kMaxCoordinate || std::fabs(p.z) > kMaxCoordinate) {
      std::ostringstream msg;
      msg << label << ": point " << i << " (" << p.x << ", " << p.y << ", " << p.z
          << ") has a coordinate beyond +-1e18: its squared distances would overflow float32";
      throw InputError(msg.str());
    }
  }
}

}  // namespace tigris
