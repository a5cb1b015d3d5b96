// `tigris register`: the registration pipeline (registration; docs/registration.md) on two
// frames, searching through the golden model (exact or approximate), FLANN, or the accelerator
// model in the loop (accel, accel-approx: accel_in_loop.hpp); writes
// DIR/registration.json (transform, per-stage seconds and KD-tree work, accuracy against ground
// truth when given). Exit 0 when ICP converged; 1 when it did not or the problem is degenerate
// (registration.json still written, with "status" and a warning on stderr); 2 bad input.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace tigris {

struct RegisterOptions {
  std::string source, target;
  std::uint64_t seed = 1;
  std::string preset = "dp4";
  std::string config;
  std::vector<std::string> sets;
  std::string search;        // empty: the configuration's search.backend (exact by default)
  std::string height;        // empty: search.top_height
  std::string approx_thd;    // empty: search.nn_thd / search.radius_thd
  std::string inject_kth;    // empty: inject.rpce_kth
  std::string inject_shell;  // "R1,R2"; empty: inject.normals_shell_inner/_outer
  std::string ground_truth, kitti_poses, kitti_frames = "1,0";
  bool list_config = false;
  bool json = false;         // --list-config as JSON
  bool list_stages = false;  // the pipeline's stages as JSON, for the tools
  double max_work = 1e10;
  std::string record_trace;             // workload trace of every 3D search (traces/README.md)
  std::string accel_config;             // --search accel*: the accelerator's configuration file
  std::vector<std::string> accel_sets;  // --search accel*: its KEY=VALUE settings
  bool check_flags = false;             // --check-flags: validate, then exit 0
  bool compare = false;                 // --compare: the four back-ends side by side (register_compare.cpp)
  int repeat = 3;                       // --compare: timed runs of each CPU back-end (cpu_baseline.hpp)
  int jobs = 0;                         // --search accel*: jobs simulated at a time (0: 2 with two cores)
  std::string command_line;             // as typed, for the trace's record (set by main)
  std::vector<std::string> argv;        // as given (set by main; --compare re-runs the command)
  std::string out = "tigris-out";
};

void add_register_options(CLI::App& app, RegisterOptions& o);
// The files the registration reads (source, target, configurations, ground truth), with their
// roles, for the output folder's record of its inputs.
nlohmann::json register_inputs(const RegisterOptions& o);
int run_register_command(const CLI::App& app, const RegisterOptions& o);

// `tigris register --compare`: the same registration with PCL's FLANN and the golden model on
// the CPU and with the accelerator in the loop, exact and approximate, each in a process of its
// own (OUT/<back-end>/registration.json); one table of KD-tree time, end-to-end time, KD-tree
// energy and error, printed and in OUT/comparison.json.
int run_register_compare(const CLI::App& app, const RegisterOptions& o);

}  // namespace tigris
