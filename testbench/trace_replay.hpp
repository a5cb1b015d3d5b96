// A registration's workload trace (traces/README.md) replayed through the accelerator model,
// job by job, as the host would run it (`tigris run --trace`): the tree image and queries written
// over the host link, the search simulated, the results read back. Every query of every job is
// checked against the golden model (approximate: the golden replay of the hardware's schedule)
// and compared with the results the pipeline recorded. Reports per job (OUT/jobs/), per stage and
// in total, and the registration's end-to-end time with its KD-tree searches on the accelerator
// (docs/registration.md).
//
// Each job runs in a child process of its own (SystemC elaborates once per process), `jobs` at a
// time; a job's figures do not depend on how many run at once.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hw/config.hpp"
#include "sw_ref/work_guard.hpp"
#include "traces/workload_trace.hpp"

namespace tigris {

struct TraceReplay {
  std::string trace;           // the trace's path (messages name it)
  std::string trace_stages;    // comma-separated stages to replay (empty: all)
  std::string out;             // each job's report goes to OUT/jobs/
  hw::AcceleratorConfig cfg;   // validated
  bool height_chosen = false;  // cfg.tree.top_height over each job's recorded height
  WorkLimits limits;
  int jobs = 1;         // jobs simulated at a time
  int sim_threads = 0;  // with one job at a time (0: default_sim_threads())
};

struct ReplayedJob {
  std::size_t index;  // in the trace
  bool send_tree;     // the previous replayed job searched another tree
};

// The jobs' reports, summed per stage and in total, and the registration end to end.
struct ReplayResult {
  nlohmann::json jobs = nlohmann::json::array(), per_stage = nlohmann::json::object(), total = nlohmann::json::object(),
                 end_to_end;
  bool all_match = true;
  std::size_t sampled = 0;  // jobs whose cycles and energy are estimates (docs/sampling.md)
};

// The jobs of o.trace_stages (default: all) in the trace's order; refuses a stage the trace has
// no searches in.
std::vector<ReplayedJob> plan_replay(const trace::Trace& t, const TraceReplay& o);
// Replays the plan; throws naming the first job that failed with an error.
ReplayResult replay_trace(const trace::Trace& t, const TraceReplay& o, const std::vector<ReplayedJob>& plan);
// stats.json's fields of a replay (docs/stats.md): trace, verdict, config, stages, total, jobs,
// sampled_jobs, end_to_end.
nlohmann::json replay_stats(const trace::Trace& t, const TraceReplay& o, std::size_t replayed, const ReplayResult& c);
// The summary on stdout (a row per stage in the pipeline's order, the total, end to end); the
// first mismatching job on stderr.
void print_replay(const trace::Trace& t, const TraceReplay& o, std::size_t replayed, const ReplayResult& c,
                  const std::string& stats_path);

}  // namespace tigris
