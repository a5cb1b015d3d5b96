// The one accelerator job runner, shared by `tigris run`, `tigris run --trace` (replay) and
// `tigris register --search accel` (in the loop; docs/registration.md): prepare the job (the
// tree, its image, the fit and work checks), search it with the golden model, simulate it as the
// host runs it (tree image and queries over the host link, the search, the results read back),
// and check every query against the golden model (approximate: the golden replay of the
// hardware's schedule). SystemC elaborates once per process: simulate once per (child) process.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hw/config.hpp"
#include "scoreboard.hpp"
#include "simulation.hpp"
#include "sw_ref/cloud.hpp"
#include "sw_ref/kdtree.hpp"
#include "sw_ref/results.hpp"
#include "sw_ref/search.hpp"
#include "sw_ref/work_guard.hpp"
#include "tlm/tree_image.hpp"

namespace tigris {

// A job ready to simulate: its configuration (tree height and leader settings are the job's),
// tree, tree image, CSR view and work estimate.
struct PreparedJob {
  hw::AcceleratorConfig cfg;
  KdTree tree;
  tlm_if::TreeImage image;
  HostJob job;
  WorkEstimate estimate;
};

// A tree and its image built ahead, for a job to take instead of building its own: the loop's
// model server builds one per cloud and each job, in a child forked from it, moves it out at no
// cost (docs/registration.md).
struct BuiltTree {
  KdTree tree;
  tlm_if::TreeImage image;
  static BuiltTree of(const PointCloud& points, int top_height, SplitRule split);
  // Whether it is the tree a job on `cfg` builds over `points`.
  bool fits(const PointCloud& points, const hw::AcceleratorConfig& cfg) const {
    return tree.num_points == points.size() && tree.top_height == cfg.tree.top_height &&
           tree.split == cfg.tree.split_axis;
  }
};

// Builds the tree of `points` at cfg.tree.top_height (or takes `built`'s, when it is that tree
// of these points) and checks the job: throws
// std::invalid_argument `fit_prefix` + why when it does not fit the buffers, and when the work
// estimate exceeds `limits`.
PreparedJob prepare_job(const PointCloud& points, const PointCloud& queries, const SearchParams& params,
                        const hw::AcceleratorConfig& cfg, const WorkLimits& limits, const std::string& fit_prefix,
                        BuiltTree* built = nullptr);

// What a run of the job adds to the simulation: waveforms, observers, progress, host threads.
struct SimExtras {
  std::string vcd_path, gtkw_path;  // waveforms and their GTKWave save file (empty: none)
  std::vector<std::string> provenance;
  std::vector<hw::JobObserver*> observers;
  std::function<void(std::uint32_t done, std::uint32_t total)> progress;
  int sim_threads = default_sim_threads();
  std::string every_query;  // an output that needs every query simulated ("--dump-schedule"): not sampled
};

// The job's sampling plan (sim.sampling over its queries and what it holds in flight).
SamplingPlan job_plan(const PreparedJob& p, const SearchParams& params, std::size_t queries);
// Throws when a sampled plan meets an output that shows every query: waveforms or a timeline
// (`waves`), or `every_query` naming another ("--dump-schedule ..."). Commands call it before
// they claim their folder; run_job again.
void check_every_query(const SamplingPlan& plan, bool waves, const std::string& every_query);

// What the job measured: the golden model's exact search, the simulation and the check.
struct JobOutcome {
  SearchOutput golden;  // exact, in query order (an approximate job is measured against it)
  SimOutcome sim;       // sim.finished false: a deadlock (sim.deadlock says where)
  Verdict verdict;      // set when the simulation finished
  double golden_seconds = 0, sim_seconds = 0, check_seconds = 0;
};

// Searches, simulates (on a thread of its own: SystemC's stack switches confuse the sanitizers'
// view of the main thread) and checks. Throws std::invalid_argument when the accelerator
// rejected the job.
JobOutcome run_job(const PreparedJob& p, const PointCloud& points, const PointCloud& queries,
                   const SearchParams& params, const SimExtras& extras);

// ---------------------------------------------------------------------------------------------
// A job of a registration (replayed or in the loop), with the host link's cost.

struct ModelJob {
  const PointCloud* points = nullptr;  // the tree's points
  const PointCloud* queries = nullptr;
  SearchParams params;
  int top_height = 10;         // clamped to the cloud's full height
  bool send_tree = true;       // the host writes the tree image first
  BuiltTree* built = nullptr;  // the tree of `points`, if built ahead (moved out by the job)
};

struct ModelJobRun {
  bool match = false;  // every query bit-exact (false: see report["mismatches"] or ["deadlock"])
  Results results;     // the accelerator's
  VisitTotals visits;  // the accelerator's
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
ModelJobRun run_model_job(const ModelJob& job, hw::AcceleratorConfig cfg, const WorkLimits& limits, int sim_threads);

}  // namespace tigris
