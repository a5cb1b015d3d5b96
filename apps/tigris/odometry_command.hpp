// `tigris odometry` (docs/registration.md): registers each frame of a KITTI-layout
// sequence (or of a synthetic drive it writes first, `--synthetic N`) into the previous one and
// chains the poses. Each pair is `tigris register` run as a process of its own with the pipeline
// flags forwarded (so a pair's registration.json is exactly what `tigris register` would write),
// `--jobs N` at a time or all as one Slurm job array (`--slurm`); a rerun into the same OUT with
// the same settings reuses the pairs already there. Writes OUT/poses.txt (KITTI format),
// OUT/pairs.csv and OUT/metrics.json (the KITTI devkit's metrics when the sequence has
// poses.txt; the accelerator's totals with --search accel*). `--compare` runs four back-ends
// side by side (odometry_compare.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/slurm_array.hpp"

namespace tigris {

struct OdometryOptions {
  std::string sequence;    // a KITTI-layout folder, or:
  int synthetic = 0;       // frames of a synthetic drive, written to OUT/sequence
  std::uint64_t seed = 1;  // its seed
  std::string frames;      // "A:B", first and last frame (default: all)
  int jobs = 1;
  std::string out = "tigris-odometry";
  // Forwarded to each pair's `tigris register` as given.
  std::string preset = "dp4", config, search, height, approx_thd, accel_config;
  std::vector<std::string> sets, accel_sets;
  double max_work = 1e10;
  SlurmOptions slurm;             // --slurm: the pairs as one job array
  bool compare = false;           // --compare: flann, exact, approx and accel side by side (odometry_compare.cpp)
  int repeat = 3;                 // --compare: runs of each CPU back-end (cpu_baseline.hpp)
  std::vector<std::string> argv;  // as given (set by main)
  std::string command_line;
};

void add_odometry_options(CLI::App& app, OdometryOptions& o);
// --compare: the options of each back-end's odometry (flann, exact, approx, accel).
std::vector<OdometryOptions> compare_variants(const OdometryOptions& o);

int run_odometry_command(const CLI::App& app, const OdometryOptions& o);
int run_odometry_compare(const OdometryOptions& o);

}  // namespace tigris
