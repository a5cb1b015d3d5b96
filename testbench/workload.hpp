// The workload of a run: the cloud the tree is built on and the queries, from files or the
// built-in synthetic LiDAR pair (the default, so every command works without external data).
#pragma once

#include <cstdint>
#include <string>

#include "sw_ref/cloud.hpp"

namespace tigris {

struct Workload {
  PointCloud cloud, queries;
  std::string cloud_name, queries_name;  // file path, or "synthetic:frame0 (seed S)"
};

// Empty paths select the synthetic frames of `seed`: frame 0 as cloud, frame 1 as queries.
Workload load_workload(const std::string& cloud_path, const std::string& queries_path,
                       std::uint64_t seed);

}  // namespace tigris
