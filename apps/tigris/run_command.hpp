// `tigris run`: the accelerator model on a workload, every query checked against the golden
// model; exit 0 only when all match.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hw/config.hpp"
#include "options.hpp"

namespace tigris {

struct RunOptions {
  SearchOptions search;
  std::string config_file;
  std::vector<std::string> settings;  // --set key=value
  bool list_config = false;
  bool json = false;          // --list-config as JSON
  bool stats_schema = false;  // print the stats.json schema
  std::string vcd;
  std::string timeline;                   // Chrome trace-event JSON
  std::uint32_t timeline_queries = 2000;  // about this many queries appear in it
  int sim_threads = 0;                    // 0: default_sim_threads()
  std::string trace;                      // replay a registration's workload trace
  std::string trace_stages;               // comma-separated stages to replay (empty: all)
  int jobs = 1;                           // trace jobs simulated at a time
};

void add_run_options(CLI::App& app, RunOptions& o);
int run_run_command(const CLI::App& app, const RunOptions& options);
// The accelerator's configuration: --config, then --set, then --height and --split-axis over
// them (run and run --trace; not yet validated: run lays its leader flags over it first).
hw::AcceleratorConfig accelerator_config(const CLI::App& app, const RunOptions& o);

}  // namespace tigris
