// `tigris synth`: writes the synthetic drive of workloads/synthetic/drive.hpp in KITTI's
// odometry layout, so any KITTI tool reads it: velodyne/NNNNNN.bin (float32 x, y, z,
// reflectance 0), poses.txt (cam0 poses, frame i in frame 0), calib.txt (Tr: the exact axis swap
// Velodyne -> camera; P0..P3: a nominal camera, KITTI 00's intrinsics, no images), times.txt, and
// drive.json (the settings, what the town holds, per frame time, speed and distance).
#pragma once

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

#include "workloads/synthetic/drive.hpp"

namespace tigris {

struct SynthOptions {
  int frames = 0;
  std::uint64_t seed = 1;
  int jobs = 2;
  std::string out;
};

void add_synth_options(CLI::App& app, SynthOptions& o);
int run_synth_command(const CLI::App& app, const SynthOptions& o);

// Writes (or completes: the scans already there are kept when drive.json has the same
// settings) the drive in `dir`; `jobs` scans cast at once. Progress on stderr unless quiet.
// Throws std::invalid_argument when `dir` holds another drive or other files' poses.txt.
void write_synthetic_drive(const DriveConfig& config, const std::string& dir, int jobs, bool quiet);

}  // namespace tigris
