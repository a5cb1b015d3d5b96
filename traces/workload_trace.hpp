// The workload trace of a registration (docs/registration.md; format in traces/README.md): every
// 3D KD-tree search the pipeline made, grouped into accelerator jobs, with the clouds they
// searched (each stored once, by content hash), the results the pipeline received and the CPU
// seconds they took. `tigris register --record-trace` writes one; `tigris run --trace` replays
// it through the accelerator model.
//
// A job = the queries one stage sent to one tree with one parameter set, in the pipeline's
// order; a new job starts whenever the stage, the tree, the parameters or the ICP iteration
// change (traces/README.md, "Jobs").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sw_ref/cloud.hpp"

namespace tigris::trace {

constexpr std::uint32_t kVersion = 1;

// FNV-1a 64 of the points' float32 bytes (little-endian x, y, z per point): the key a cloud is
// stored under.
std::uint64_t content_hash(const PointCloud& points);
std::string hash_text(std::uint64_t hash);  // 16 hex digits

struct Cloud {
  std::uint64_t hash = 0;
  PointCloud points;
};

struct Job {
  std::string stage;          // outlier_removal, normals, keypoints, descriptors, icp
  int iteration = -1;         // ICP iteration from 0; -1 outside ICP
  std::string backend;        // flann | exact | approx: what answered the searches on the CPU
  std::uint64_t tree = 0;     // content hash of the cloud the tree was built on
  std::uint64_t queries = 0;  // content hash of the query points, in call order
  int tree_serial = 0;        // which tree object (two trees on equal clouds stay apart)
  int top_height = 10;        // asked for; the replay clamps it to the cloud's full height
  // The search as issued to the tree (after error injection widened it: k + K - 1, the shell's
  // outer radius): mode nn | knn | radius.
  std::string mode = "nn";
  int k = 1;
  float radius = 0.0f;
  std::uint32_t max_nn = 0;
  bool approximate = false;
  float approx_thd = 0.0f;
  int leader_capacity = 16, leader_width = 0;
  // Approximate search's reading (sw_ref/leader_policy.hpp): a trace without these keys was
  // recorded before first_leaf existed, so it reads as every_leaf.
  std::string leader_scope = "first_leaf", leader_in_flight = "wait";
  // Error injection the pipeline applied to these results afterwards (1 / 0: none).
  int inject_kth = 1;
  float shell_inner = 0.0f, shell_outer = 0.0f;
  double search_seconds = 0.0;  // CPU seconds of the job's searches
  double build_seconds = 0.0;   // CPU seconds of building its tree (charged to the tree's first job)
  // The results the searches returned, per query in the order returned: counts[q] indices
  // into the tree cloud. dist2 is not stored: it is the contract's dist2 (sw_ref/arith.hpp) of
  // the query and the point, recomputed by results().
  std::vector<std::uint32_t> counts;
  std::vector<std::uint32_t> indices;
};

struct Stage {
  std::string name;
  double seconds = 0.0;  // wall seconds of the whole stage on the CPU
  double kdtree_search_seconds = 0.0, kdtree_build_seconds = 0.0;
};

struct Trace {
  nlohmann::json meta = nlohmann::json::object();  // tool, command line, inputs, preset, transform
  std::vector<Stage> stages;
  double total_seconds = 0.0;
  std::vector<Cloud> clouds;
  std::vector<Job> jobs;

  // The cloud stored under `hash`; throws std::out_of_range when there is none.
  const Cloud& cloud(std::uint64_t hash) const;
  // Adds a cloud unless one with its hash is stored; returns the hash.
  std::uint64_t add_cloud(const PointCloud& points);
};

// The job's results with dist2 recomputed, in the order recorded.
struct JobResults {
  std::vector<std::uint64_t> offset{0};
  std::vector<std::uint32_t> index;
  std::vector<float> dist2;
};
JobResults results(const Trace& trace, const Job& job);

// The file's bytes (the caller writes them; tigris register through write_file, which writes
// beside the path and renames over it).
std::vector<std::uint8_t> encode(const Trace& trace);

// Throws InputError "LABEL: byte N: what" on a truncated, foreign, corrupt or newer-version
// file, or one whose contents contradict themselves (a job naming a missing cloud, result
// indices beyond their cloud, counts that do not add up).
Trace decode(const std::uint8_t* data, std::size_t size, const std::string& label);
Trace read_trace(const std::string& path);

}  // namespace tigris::trace
