// One search job through the accelerator model as the host runs it (issue 19;
// docs/registration.md): the tree image written over the host link (when the job searches another tree
// than the job before), the queries written, the search simulated, the results read back, and
// every query checked against the golden model (approximate: the golden replay of the
// hardware's schedule). Shared by `tigris run --trace` (replay) and `tigris register --search
// accel` (in the loop). SystemC elaborates once per process: call it once per (child) process.
#pragma once

#include <cstdint>

#include <nlohmann/json.hpp>

#include "hw/config.hpp"
#include "sw_ref/cloud.hpp"
#include "sw_ref/results.hpp"
#include "sw_ref/search.hpp"
#include "work_guard.hpp"

namespace tigris {

struct ModelJob {
  const PointCloud* points = nullptr;   // the tree's points
  const PointCloud* queries = nullptr;
  SearchParams params;
  int top_height = 10;     // clamped to the cloud's full height
  bool send_tree = true;   // the host writes the tree image first
};

struct ModelJobRun {
  bool match = false;      // every query bit-exact (false: see report["mismatches"] or ["deadlock"])
  Results results;         // the accelerator's
  VisitTotals visits;      // the accelerator's
  std::uint64_t cycles = 0;
  double search_seconds = 0.0, host_seconds = 0.0, energy_pj = 0.0;
  // verdict, mismatches, cycles, top_height, modeled_seconds {search, host, total}, host_bytes,
  // energy_pj, neighbors, visits, units, wall_seconds.
  nlohmann::json report = nlohmann::json::object();
};

// Host link time of one transfer of `bytes`: latency + bytes / bandwidth (config block host).
double link_seconds(const hw::AcceleratorConfig& cfg, double bytes);

// Runs `job` on an accelerator configured by `cfg` (its tree height and, for approximate
// search, its leader capacity are the job's). Throws std::invalid_argument when the job does
// not fit the accelerator or exceeds `limits`.
ModelJobRun run_model_job(const ModelJob& job, hw::AcceleratorConfig cfg, const WorkLimits& limits,
                          int sim_threads);

}  // namespace tigris
