// registration.json, the one place that knows it (docs/registration.md#registrationjson): the
// typed report `tigris register` writes, and the reader odometry (a pair's result, resumable)
// and `register --compare` (a back-end's row) take it back with. Reading then writing a report
// gives it back byte for byte; a report that is not whole (edited, truncated) is an error naming
// the file and the key.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "accelerator_port.hpp"
#include "pipeline.hpp"
#include "workloads/pose.hpp"

namespace tigris::registration {

struct Report {
  // 1: the first versioned layout. A report without "version" (written before it) reads as 1.
  static constexpr int kVersion = 1;

  struct Cloud {
    std::string name;
    std::uint64_t points = 0;
  };
  struct Injection {  // config.inject, as the summary says it; shell_outer 0: no shell
    int rpce_kth = 1;
    double shell_inner = 0, shell_outer = 0, normals_radius = 0;
  };
  struct Truth {
    std::string source;  // where it came from (a file, KITTI poses and frames, the synthetic pair)
    Pose transform = Pose::Identity();
    std::string warning;  // e.g. KITTI 00's equal first steps
  };
  struct Accelerator {                // the accelerator in the loop (--search accel*): what the stages do not hold
    nlohmann::ordered_json sampling;  // sim.sampling's setting
    nlohmann::ordered_json config;    // the accelerator's keys
    nlohmann::ordered_json job_list = nlohmann::ordered_json::array();  // a row a job
  };

  Cloud source, target;
  std::string preset;
  std::string search;  // as asked: flann, exact, approx, accel or accel-approx
  Injection injection;
  RegistrationResult result;  // status, transform (NaN when degenerate), stages, seconds
  double work_spent = 0, max_work = 0;
  std::optional<Accelerator> accelerator;
  std::optional<Truth> truth;    // written only when the registration is not degenerate
  nlohmann::json config;         // the pipeline's keys
  nlohmann::ordered_json trace;  // --record-trace: {path, jobs, clouds}; null when none

  bool degenerate() const { return result.status == "degenerate"; }
  bool in_loop() const { return accelerator.has_value(); }
  // Against the ground truth (none without one, or when degenerate); of the initial guess too.
  std::optional<PoseError> error() const;
  std::optional<PoseError> initial_error() const;
  // The stages' KD-tree builds and searches on the CPU (wall time; in the loop: the simulation's).
  double kdtree_seconds() const;
  std::uint64_t sampled_jobs() const;  // accelerator jobs whose figures are estimates
};

// A stage's KD-tree time with the accelerator in the loop: its jobs as modeled (search and host
// transfers) plus the searches it could not batch, at their CPU time.
double modeled_kdtree_seconds(const SearchCounters& k);
double modeled_stage_seconds(const StageReport& s);

// The registration in the loop as modeled: end to end, KD-tree time and energy over the stages.
struct LoopFigures {
  double modeled_e2e = 0, modeled_kd = 0, energy_pj = 0;
  std::uint64_t jobs = 0, fallback_searches = 0;
};
LoopFigures loop_figures(const RegistrationResult& r);

// The injected error of a configuration (config.inject), as the report holds it.
Report::Injection injection_of(const PipelineConfig& config);
// An accelerator job's row of the report's job_list: what it searched and what the model's
// job report (testbench/accel_job.hpp) says of it.
nlohmann::ordered_json job_row(std::uint64_t n, const AccelJob& job, const nlohmann::json& rep,
                               const std::string& stage);

nlohmann::ordered_json matrix_json(const Eigen::Matrix4d& t);
// The transform as registration.json holds it: null when degenerate.
nlohmann::ordered_json transform_json(const Report& r);

nlohmann::ordered_json to_json(const Report& r);
// `source` names the file in errors: "<source>: <what>; not a whole tigris register report".
Report report_from_json(const nlohmann::ordered_json& doc, const std::string& source);
Report read_report(const std::string& path);

}  // namespace tigris::registration
