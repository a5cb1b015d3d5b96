// The registration pipeline (the paper's Table 1; docs/registration.md): statistical outlier
// removal, normal estimation, key points, descriptors, KPCE, correspondence rejection and ICP
// (RPCE + transformation estimation). Source = the later frame, target = the earlier; the result
// maps source points into the target frame.
//
// Every 3D KD-tree search (outlier removal, normals, key points that search, descriptors and
// their reference frames, RPCE both ways when reciprocal) goes through a TigrisKdTree charged to
// its stage. With search.backend = approx only the paper's approximated stages (normals: radius
// search, ICP's RPCE: NN search) search approximately; the others search exactly on the golden
// model (the paper: approximation in sparse data hurts). KPCE searches feature space with PCL's
// exact FLANN KD-tree, never the 3D plug-in. Error injection (config block `inject`, the paper's
// Figure 5) goes only to the normal-estimation trees (a shell instead of the ball) and ICP's
// RPCE trees (the K-th nearest neighbour), both directions when reciprocal. Single-threaded:
// never PCL's OMP classes (the approximate leader state is order dependent).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "pipeline_config.hpp"
#include "search_plugin.hpp"
#include "sw_ref/cloud.hpp"

namespace tigris::registration {

struct StageReport {
  std::string name;       // outlier_removal, normals, keypoints, descriptors, kpce, rejection, icp
  double seconds = 0.0;   // wall time of the whole stage (both clouds)
  std::string search;     // the 3D back-end its KD-tree searches used ("" when none)
  SearchCounters kdtree;  // the stage's 3D KD-tree builds and searches
  nlohmann::json info = nlohmann::json::object();  // stage-specific counts
};

struct RegistrationResult {
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();  // target <- source (final)
  Eigen::Matrix4d initial = Eigen::Matrix4d::Identity();    // after rejection, ICP's guess
  std::vector<StageReport> stages;
  double total_seconds = 0.0;
  // "converged"; "not_converged" (ICP ran out of correspondences or failed: the transform is
  // its last estimate, not a registration); "degenerate" (no rigid transform is determined,
  // e.g. a flat scene: the transform is NaN). `problem` says why when not converged.
  std::string status = "converged";
  std::string problem;
};

// A stage of the pipeline as the tools name it: registration.json's `stages.<key>`, the paper's
// title, and the paper's parts when the paper splits it (ICP: RPCE, its KD-tree searches, and
// transformation estimation, the rest; `time` says which of the stage's seconds each part is).
struct StagePart {
  std::string title;
  std::string time;  // "kdtree_search" or "rest"
};
struct StageInfo {
  std::string key, title;
  std::vector<StagePart> parts;
};

// The stages in the pipeline's order (`tigris register --list-stages` prints them for the tools).
std::vector<StageInfo> stage_list();
nlohmann::json stage_list_json();

// Called at the start of each stage with its name (for progress on stderr).
using StageCallback = std::function<void(const std::string& stage)>;

// What a caller hooks into a registration: progress, a work bound shared by every tree, a
// trace recorder, the accelerator in the loop (golden back-ends only; each may be empty).
struct PipelineHooks {
  StageCallback on_stage;
  std::shared_ptr<WorkBudget> budget;
  std::shared_ptr<TraceRecorder> recorder;
  std::shared_ptr<AcceleratorPort> accelerator;
};

// Runs the pipeline. Throws std::runtime_error when a stage cannot go on (e.g. no key point
// survives), WorkLimitExceeded when the searches exceed the hooks' budget. `config` must have
// been validated (apply_json / preset).
RegistrationResult register_clouds(const PointCloud& source, const PointCloud& target, const PipelineConfig& config,
                                   const PipelineHooks& hooks = {});

}  // namespace tigris::registration
