// A sequence's odometry from its pairs' registration reports (`tigris odometry`,
// docs/registration.md#odometry): the trajectory chained pair by pair, the sums over the pairs
// and per stage, and the files' contents: pairs.csv, trajectory.csv and metrics.json's figures
// with the KITTI devkit's errors (odometry_metrics.hpp). No files and no processes here: the
// command runs the pairs and writes what this unit computes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "report.hpp"
#include "workloads/pose.hpp"

namespace tigris::registration {

class Odometry {
 public:
  // Pair k registered frame first + k + 1 (source) into frame first + k (target). `poses`: the
  // sequence's ground truth for every frame (empty: none). `accel`: the pairs ran in the loop
  // (their reports have the accelerator's figures). Throws std::invalid_argument at a degenerate
  // pair: the trajectory cannot be chained past it.
  Odometry(std::size_t first, std::vector<Report> pairs, const std::vector<Pose>& poses, bool accel);

  struct Totals {
    double seconds = 0, kd = 0, modeled_e2e = 0, modeled_kd = 0, energy_pj = 0;
    std::size_t not_converged = 0;
    std::uint64_t jobs = 0, sampled_jobs = 0;  // accelerator jobs, and those sampled (estimated figures)
  };

  std::size_t pairs() const { return pairs_.size(); }
  const std::vector<Pose>& estimated() const { return est_; }  // frames first.., frame first the identity
  const std::vector<Pose>& truth() const { return gt_; }       // anchored at frame first; empty: none
  const Totals& totals() const { return sum_; }
  bool accel() const { return accel_; }

  void write_pairs_csv(std::ostream& out) const;       // a line a pair
  void write_trajectory_csv(std::ostream& out) const;  // positions, estimated and ground truth
  // metrics.json's figures, appended to `m` (the run's own head): not_converged_pairs, totals,
  // accelerator, per-stage means, and the errors against the ground truth (kitti, ate, rpe,
  // ground_truth_warning when its first steps are equal and `synthetic_truth` is false) or
  // ground_truth null. Returns the summary's note ("" when none).
  std::string add_metrics(nlohmann::ordered_json& m, bool synthetic_truth) const;
  // The summary `tigris odometry` prints: the frames, the totals, the accelerator's modeled
  // figures, the errors from metrics.json's figures `m`, and `note`. `search`: the back-end.
  void print_summary(std::FILE* out, const nlohmann::ordered_json& m, const std::string& sequence,
                     const std::string& search, const std::string& note) const;

 private:
  void add_pair(std::size_t k);

  std::size_t first_;
  std::vector<Report> pairs_;
  std::vector<Pose> poses_from_first_;  // the ground truth from frame first to its end
  bool accel_;
  std::vector<Pose> est_, gt_;
  Totals sum_;
  std::map<std::string, nlohmann::ordered_json> stages_;  // per stage, by name: sums over the pairs
};

}  // namespace tigris::registration
