// `tigris run --trace FILE`: its flags checked, then the replay (testbench/trace_replay.hpp) into
// the output folder, stats.json and the summary.
#pragma once

#include "run_command.hpp"

namespace tigris {

int run_trace_replay(const CLI::App& app, const RunOptions& options);

}  // namespace tigris
