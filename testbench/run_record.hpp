// What `tigris run` records of a finished run: stats.json (docs/stats.md: the run, the
// accelerator's statistics, the derived fields from their formulas, the bound and the
// configuration that produced them) and the summary lines on stdout.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "accel_job.hpp"
#include "sw_ref/accuracy.hpp"
#include "sw_ref/search.hpp"
#include "workloads/workload.hpp"

namespace tigris {

// What `tigris run` simulates: the checked configuration, the workload, its tree and the job.
struct RunSetup {
  SearchParams params;
  Workload w;
  nlohmann::json inputs;  // input_file() records of the files read
  PreparedJob p;          // configuration, tree, image, job, work estimate
};

// The configuration as stats.json records it: the accelerator's keys, and the search and
// approximation settings of this run. Its SHA-256 identifies the configuration in every output.
nlohmann::json run_config_json(const RunSetup& r);
// stats.json of a finished, checked run; `accuracy` is set for an approximate one. Throws when
// the configuration made a figure non-finite (naming the field).
nlohmann::json run_stats(const RunSetup& r, const JobOutcome& m, const std::string& command_line, Accuracy& accuracy);
// The summary lines: verdict, inputs, configuration, cycles and bound, units, visits, latency,
// the approximation and its accuracy, energy and area, wall times, where stats.json is.
void print_run_summary(const RunSetup& r, const JobOutcome& m, const nlohmann::json& stats, const Accuracy& accuracy,
                       const std::string& stats_path);

}  // namespace tigris
