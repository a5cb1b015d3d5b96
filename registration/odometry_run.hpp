// One back-end's odometry of a sequence (`tigris odometry`, docs/registration.md#odometry), in
// the order it runs: the sequence read, OUT claimed (keyed on every input the pairs read), each
// pair registered as a `tigris register` child in OUT/pairs/<target frame>/ (here or as one Slurm
// array: core/child_batch.hpp; a rerun resumes from the reports there), the poses chained
// (odometry.hpp), and poses.txt, trajectory.csv, pairs.csv and metrics.json written. The summary
// and the plots are the command's.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/out_folder.hpp"
#include "core/slurm_array.hpp"
#include "odometry.hpp"
#include "report.hpp"
#include "workloads/kitti_sequence.hpp"

namespace tigris::registration {

struct OdometrySettings {
  std::string sequence;            // a KITTI-layout folder
  std::string frames;              // "A:B", the first and the last frame (empty: every frame)
  std::string out;                 // OUT
  std::vector<std::string> flags;  // each pair's `tigris register` flags (also the resume key)
  bool accel = false;              // the pairs run in the loop: their reports carry the accelerator's figures
  int jobs = 1;                    // pairs registered at once here
  SlurmOptions slurm;              // slurm.slurm: the pairs as one job array
  nlohmann::json config_inputs = nlohmann::json::array();  // the configuration files the pairs read
  std::string command_line;
};

// "000042": a frame's name in KITTI's layout and in OUT/pairs/.
std::string frame_tag(std::size_t i);
// What OUT holds: one back-end's odometry, or --compare's back-ends side by side.
std::vector<std::string> odometry_outputs(bool compare);

class OdometryRun {
 public:
  // `claimed`: OUT when already claimed (the synthetic drive claims it first); null: run() claims it.
  OdometryRun(OdometrySettings settings, std::unique_ptr<OutFolder> claimed);
  // Every step up to metrics.json. False: the pairs were submitted with --no-wait (OUT finished).
  // Throws naming the first pair that failed; the pairs done are kept.
  bool run();

  const Odometry& odometry() const { return *odometry_; }
  const nlohmann::ordered_json& metrics() const { return metrics_; }  // metrics.json
  const std::string& note() const { return note_; }                   // the summary's note ("" when none)
  OutFolder& folder() { return *folder_; }

 private:
  void read_sequence();
  void claim_folder();
  void plan_pairs();
  bool run_pairs();
  void write_files();

  OdometrySettings o;
  std::unique_ptr<OutFolder> folder_;
  KittiSequence seq_;
  std::size_t first_ = 0, last_ = 0, pairs_ = 0;  // the frames registered, pairs = last - first
  std::vector<Report> regs_;                      // each pair's registration.json
  std::vector<std::size_t> todo_;                 // the pairs still to register
  std::unique_ptr<Odometry> odometry_;            // chained, once every pair is registered
  nlohmann::ordered_json metrics_;
  std::string note_;
};

}  // namespace tigris::registration
