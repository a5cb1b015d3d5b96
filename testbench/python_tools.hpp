// `tigris sweep ...` and `tigris reproduce ...`: the design-space tools are Python scripts in
// sweep/ (DESIGN.md section 17); these subcommands run them with this binary as their `tigris`.
#pragma once

namespace tigris {

// If argv names a Python tool, runs it in place of this process (returns only on failure, with
// the exit code); otherwise returns -1.
int run_python_tool(int argc, char** argv);

}  // namespace tigris
