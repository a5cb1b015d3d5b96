// `tigris ref`: the golden model alone on a workload; prints a summary, writes stats.json and
// the optional results/schedule dumps.
#pragma once

#include "options.hpp"

namespace tigris {

int run_ref_command(const CLI::App& app, const SearchOptions& options);

}  // namespace tigris
