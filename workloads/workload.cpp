#include "workload.hpp"

#include <stdexcept>

#include "synthetic.hpp"
#include "workloads/io/cloud_io.hpp"

namespace tigris {

Workload load_workload(const std::string& cloud_path, const std::string& queries_path, std::uint64_t seed) {
  // Queries without a cloud would search the user's points in the synthetic street: nonsense
  // that still MATCHes, so it is refused.
  if (cloud_path.empty() && !queries_path.empty())
    throw std::invalid_argument("--queries " + queries_path + " needs --cloud (the cloud its points are searched in)");
  Workload w;
  if (cloud_path.empty()) {
    SyntheticConfig config;
    config.seed = seed;
    SyntheticPair pair = make_synthetic_pair(config);
    const std::string tag = " (seed " + std::to_string(seed) + ")";
    w.cloud = std::move(pair.frame0);
    w.queries = std::move(pair.frame1);
    w.cloud_name = "synthetic:frame0" + tag;
    w.queries_name = "synthetic:frame1" + tag;
    return w;
  }
  w.cloud = load_cloud(cloud_path);
  w.cloud_name = cloud_path;
  if (queries_path.empty()) {
    w.queries = w.cloud;  // a cloud alone is searched in itself, as normal estimation does
    w.queries_name = cloud_path + " (the cloud itself)";
  } else {
    w.queries = load_cloud(queries_path);
    w.queries_name = queries_path;
  }
  return w;
}

}  // namespace tigris
