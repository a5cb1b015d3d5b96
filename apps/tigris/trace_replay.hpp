// `tigris run --trace FILE`: replays a registration's workload trace (traces/README.md) through
// the accelerator model, job by job, as the host would run it: the tree image and queries
// written over the host link, the search simulated, the results read back. Every query of every
// job is checked against the golden model (approximate: the golden replay of the hardware's
// schedule) and compared with the results the pipeline recorded. Reports per job, per stage and
// in total, and the registration's end-to-end time with its KD-tree searches on the
// accelerator (docs/registration.md).
//
// Each job runs in a child process of its own (SystemC elaborates once per process), --jobs N
// at a time; a job's figures do not depend on N.
#pragma once

#include "run_command.hpp"

namespace tigris {

int run_trace_replay(const CLI::App& app, const RunOptions& options);

}  // namespace tigris
