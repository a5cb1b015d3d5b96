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

// Both paths empty: the synthetic frames of `seed`, frame 0 as cloud and frame 1 as queries.
// A cloud alone is searched in itself; queries without a cloud are refused
// (std::invalid_argument).
Workload load_workload(const std::string& cloud_path, const std::string& queries_path, std::uint64_t seed);

}  // namespace tigris
