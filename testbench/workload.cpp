#include "workload.hpp"

#include <optional>

#include "sw_ref/io/cloud_io.hpp"
#include "sw_ref/synthetic.hpp"

namespace tigris {

Workload load_workload(const std::string& cloud_path, const std::string& queries_path,
                       std::uint64_t seed) {
  Workload w;
  std::optional<SyntheticPair> pair;
  auto synthetic = [&]() -> const SyntheticPair& {
    if (!pair) {
      SyntheticConfig config;
      config.seed = seed;
      pair = make_synthetic_pair(config);
    }
    return *pair;
  };
  const std::string tag = " (seed " + std::to_string(seed) + ")";
  if (cloud_path.empty()) {
    w.cloud = synthetic().frame0;
    w.cloud_name = "synthetic:frame0" + tag;
  } else {
    w.cloud = load_cloud(cloud_path);
    w.cloud_name = cloud_path;
  }
  if (queries_path.empty()) {
    w.queries = synthetic().frame1;
    w.queries_name = "synthetic:frame1" + tag;
  } else {
    w.queries = load_cloud(queries_path);
    w.queries_name = queries_path;
  }
  return w;
}

}  // namespace tigris
