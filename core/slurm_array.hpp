// Independent commands as one Slurm job array (`tigris odometry --slurm`), with the sweep tool's
// options (--partition, --time, --mem, --chunk, --sbatch-arg, --no-wait). The commands are
// written into an array script in DIR/slurm/ (one `case` branch a task, `--chunk K` commands
// each), submitted with `sbatch --parsable --array=0-M`, and waited for by polling squeue; each
// task's output goes to DIR/slurm/<job>_<task>.out and each command's to its own log.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace tigris {

struct SlurmOptions {
  bool slurm = false;
  std::string partition, time, mem;
  int chunk = 1;
  std::vector<std::string> sbatch_args;
  bool no_wait = false;
};

void add_slurm_options(CLI::App& app, SlurmOptions& o);

// sbatch is missing or refused the array: exit 3 in every command (as `tigris sweep --slurm`).
struct SlurmError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ArrayCommand {
  std::vector<std::string> argv;  // argv[0] an absolute path
  std::string log;                // stdout and stderr
  std::string parent_outputs;     // TIGRIS_PARENT_OUTPUTS for the command (children.hpp)
};

// Submits the commands; returns the job id. `dir` gets slurm/array-<stamp>.sh, slurm/job.json
// and the task logs. Throws std::runtime_error with sbatch's own message when it fails.
std::string submit_array(const SlurmOptions& o, const std::vector<ArrayCommand>& commands, const std::string& dir,
                         const std::string& name);

// Waits until `job` has no task queued or running, calling tick() about once a second. On
// SIGINT, SIGTERM or SIGHUP it cancels the job (scancel) and throws Interrupted.
void wait_array(const std::string& job, const std::function<void()>& tick);

// The job id of dir/slurm/job.json when that job is still queued or running, else "".
std::string active_array(const std::string& dir);

}  // namespace tigris
