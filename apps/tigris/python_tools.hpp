// `tigris sweep`, `reproduce`, `diff`, `plot` and `pipeline-dse`: the analysis tools of the Python
// package tigris (docs/sweeps.md), found beside this binary in ../python (the build tree) or
// ../lib/python3/dist-packages (an install; TIGRIS_PYTHONPATH overrides). They run as
// `python3 -m tigris TOOL` with this binary as their `tigris`.
#pragma once

#include <string>
#include <vector>

namespace tigris {

// If argv names a Python tool, runs it in place of this process (returns only on failure, with
// the exit code); otherwise returns -1.
int run_python_tool(int argc, char** argv);

// Runs the package's `tool` (python3 -m tigris TOOL) with `args` in a child process and waits; returns its exit code,
// or -1 with `why` set when it could not start (no package, no python3).
int run_python_module(const std::string& tool, const std::vector<std::string>& args, std::string& why);

}  // namespace tigris
