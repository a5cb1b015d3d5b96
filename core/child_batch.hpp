// A batch of this program's own commands as child processes (tigris odometry's pairs), each
// with a folder of its own and a result file there: run here as a pool, --jobs at a time, or
// on a cluster as one Slurm job array (slurm_array.hpp), both through the children core. It is
// resumable by result file: a task's result is what says it ran, so the caller lists the tasks
// whose result is not there yet, and a rerun after a stop, a failure or --no-wait does the rest.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "slurm_array.hpp"

namespace tigris {

struct ChildBatch {
  std::string program = "/proc/self/exe";  // this program (on Slurm: the path it was started from)
  std::size_t count = 0;
  // Task k's folder (created before it starts; its output goes to DIR/log.txt).
  std::function<std::string(std::size_t k)> dir;
  std::string result;  // the file a task leaves in its folder when it has run
  // Task k's arguments after the program: here, or for a node of the cluster (absolute paths).
  std::function<std::vector<std::string>(std::size_t k, bool on_slurm)> args;
  int parallel = 1;    // tasks at a time here
  SlurmOptions slurm;  // slurm.slurm: one job array, its script and logs in OUT/slurm/
  std::string out;     // the command's folder
  std::string name;    // the array's job name, and who speaks in progress lines ("tigris odometry")
  std::string noun;    // what a task is, in progress lines ("pairs")
};

struct TaskEnd {
  std::size_t k = 0;
  int code = -1;            // its exit code here; on Slurm -1 (the result says whether it ran)
  bool has_result = false;  // DIR/result is there
  std::string job;          // the Slurm job ("" here)
};

// Runs the batch. Here, `ended` runs as each task ends (false: start no further task; the running
// ones finish); on Slurm it runs for every task once the array has ended, with a progress line
// as results appear. Returns false when the array was submitted with --no-wait (its id and how to
// collect are printed on stdout).
bool run_batch(const ChildBatch& b, const std::function<bool(const TaskEnd&)>& ended);

// The last non-empty line of a task's log (for a failure's message).
std::string last_log_line(const std::string& dir);

}  // namespace tigris
