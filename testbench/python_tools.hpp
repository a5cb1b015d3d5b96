// `tigris sweep ...` and `tigris reproduce ...`: the design-space tools are Python scripts in
// sweep/ (docs/sweeps.md); these subcommands run them with this binary as their `tigris`.
#pragma once

#include <string>
#include <vector>

namespace tigris {

// If argv names a Python tool, runs it in place of this process (returns only on failure, with
// the exit code); otherwise returns -1.
int run_python_tool(int argc, char** argv);

// Runs sweep/<script> with `args` in a child process and waits; returns its exit code, or -1
// with `why` set when it could not start (no script, no python3).
int run_python_script(const std::string& script, const std::vector<std::string>& args, std::string& why);

}  // namespace tigris
