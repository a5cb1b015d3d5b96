// The one way a command starts child processes (DESIGN 23; docs/architecture.md, "The shared
// core"): locally, one at a time or as a pool, and the stop signals that end them. Each child
// leads a process group of its own and asks the kernel for SIGTERM when its parent dies
// (PR_SET_PDEATHSIG), so a child never outlives the command that started it. SIGINT, SIGTERM
// and SIGHUP to the parent alone stop every child's group (SIGTERM, SIGKILL after 5 s), mark
// the run's manifest "interrupted" and exit 128 + the signal. Fork only from the main thread:
// the death signal follows the thread that forked.
#pragma once

#include <sys/types.h>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace tigris {

// Installs the stop handlers (main() does, once). `command` names the process in the message.
void install_stop_handlers(const char* command);

// Forks a child that runs `body` and exits with its return value (3 when it throws).
pid_t fork_child(const std::function<int()>& body);

// Starts `args` (args[0] the program) as a child; its stdout and stderr go to `log` when not
// empty; `parent_outputs` (files the parent keeps in the child's --out) is passed to it as
// TIGRIS_PARENT_OUTPUTS. Throws std::runtime_error when no process can be started.
pid_t start_child(const std::vector<std::string>& args, const std::string& log = "",
                  const std::string& parent_outputs = "");

// Waits for `pid`, or for any child when pid is -1 (`ended` gets its pid); the exit code, or
// 128 + the signal that ended it.
int wait_child(pid_t pid, pid_t* ended = nullptr);

// A local pool: tasks 0..count-1, each a child process that `start(k)` starts (fork_child or
// start_child), at most `parallel` at a time, in task order. `done(k, code)` runs in the parent
// as each ends (in the order they end); false starts no further task (the running ones finish).
// When anything throws, the running children are stopped (SIGTERM to their groups) and reaped.
// Returns each task's exit code (-1: never started).
std::vector<int> run_pool(std::size_t count, int parallel, const std::function<pid_t(std::size_t)>& start,
                          const std::function<bool(std::size_t, int)>& done);

// While one lives, a stop signal is only recorded (stop_signal() returns it), for loops that
// stop cleanly themselves (a Slurm array is cancelled with scancel, then Interrupted thrown).
class DeferStop {
 public:
  DeferStop();
  ~DeferStop();
  DeferStop(const DeferStop&) = delete;
  DeferStop& operator=(const DeferStop&) = delete;
};
int stop_signal();  // the signal recorded, 0 when none

// Thrown by a loop that stopped on a signal; main() exits 128 + signal.
struct Interrupted : std::runtime_error {
  explicit Interrupted(int sig);
  int signal;
};

// What the stop message says of a rerun: resumes, or starts afresh (OutFolder sets it).
void set_rerun_note(bool resumes);

// The manifest a stop signal writes in place of a run's own (prepared while the run is calm:
// a signal handler may only write bytes). Empty `path` forgets it.
void set_interrupted_record(const std::string& path, const std::string& bytes);

// This command again for a child (`--compare`): argv (argv[0] replaced by /proc/self/exe) without
// the switches `drop_switches` and without the options `drop_options` and their values (also
// given as --option=value), then `extra`.
std::vector<std::string> rerun_args(const std::vector<std::string>& argv, const std::vector<std::string>& drop_switches,
                                    const std::vector<std::string>& drop_options,
                                    const std::vector<std::string>& extra);

}  // namespace tigris
