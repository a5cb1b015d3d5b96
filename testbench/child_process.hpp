// This program run again as a child process (`tigris register --compare`, `tigris odometry`):
// each run has a process of its own, for fair timing and independent failures.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace tigris {

// Starts /proc/self/exe with `args` (args[0] is its argv[0]); its stdout and stderr go to `log`
// when not empty. Throws std::runtime_error when no process can be started.
pid_t start_self(const std::vector<std::string>& args, const std::string& log = "");

// This command again for a child (`--compare`): argv (argv[0] replaced by /proc/self/exe) without
// the switches `drop_switches` and without the options `drop_options` and their values (also
// given as --option=value), then `extra`.
std::vector<std::string> rerun_args(const std::vector<std::string>& argv, const std::vector<std::string>& drop_switches,
                                    const std::vector<std::string>& drop_options, const std::vector<std::string>& extra);

// Waits for `pid`; its exit code, or 128 + the signal that ended it.
int wait_child(pid_t pid);

}  // namespace tigris
