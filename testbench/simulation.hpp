// Elaborates one or more accelerators, each with its own host driver, and simulates them side
// by side in one SystemC run (SystemC elaborates once per process, so a test compares several
// configurations this way). The run ends when no event is left; an accelerator whose host has
// not seen the done interrupt by then is deadlocked, and its stuck state is reported.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host_driver.hpp"
#include "hw/config.hpp"
#include "hw/top.hpp"
#include "sampling.hpp"
#include "sw_ref/results.hpp"
#include "sw_ref/search.hpp"
#include "tlm/tree_image.hpp"

namespace tigris {

// 2 on a machine with two or more cores, else 1.
int default_sim_threads();

struct SimSetup {
  hw::AcceleratorConfig config;
  const tlm_if::TreeImage* image = nullptr;
  const PointCloud* queries = nullptr;
  std::uint32_t num_points = 0;
  HostJob job;
  std::string vcd_path;                 // waveforms when not empty
  std::string gtkw_path;                // their GTKWave save file when not empty (the command's claim decides)
  std::vector<std::string> provenance;  // what made the run, for the VCD's $comment and the .gtkw
  std::function<void(hw::TigrisAccelerator&)> test_hook;  // tests: faults injected before the run
  bool reverse_construction = false;                      // tests: RUs and SUs built in reverse id order
  std::vector<hw::JobObserver*> observers;                // more observers to attach (e.g. a timeline)
  // Host threads for the simulation: 2 runs exact NN/kNN scans on a second thread
  // (hw/host/threaded_scans.hpp); the figures do not depend on it.
  int sim_threads = default_sim_threads();
  // Sampled simulation: `queries` are the plan's stream, and the figures are the job's estimate.
  const SamplingPlan* sampling = nullptr;
  QueryWork sampling_work;  // ... and what the golden model counted per job query
};

// What one run of a job left: its cycles, results, recorded visits and stats JSON.
struct RunRecord {
  std::uint64_t cycles = 0;
  Results results;
  SearchOutput visits;
  nlohmann::json stats;  // units, buffers, energy_pj, power_w, area_mm2
};

struct SimOutcome {
  bool finished = false;
  std::string error;     // the job was rejected or a transaction failed
  std::string deadlock;  // the stuck state when the simulation ran out of events early
  Results results;
  std::uint64_t cycles = 0;
  SearchOutput visits;  // per-query visit counts and the schedule, as the scoreboard recorded
  // The stats JSON's `units`, `buffers`, `energy_pj`, `power_w`, `area_mm2`.
  nlohmann::json units, buffers, energy, power_w, area;
  nlohmann::json latency;       // `latency_cycles`: per query and per BQB wait
  nlohmann::json sampling;      // sampled: the plan, the windows and the intervals (sampling.hpp)
  std::vector<RunRecord> runs;  // every run when the job ran more than once (job.runs > 1)
};

using SimProgress = std::function<void(std::uint32_t done, std::uint32_t total)>;

std::vector<SimOutcome> simulate(const std::vector<SimSetup>& setups, const SimProgress& progress = {});

// The GTKWave save file written beside waveforms `vcd_path`: the same name, extension .gtkw.
std::string gtkw_path(const std::string& vcd_path);

}  // namespace tigris
