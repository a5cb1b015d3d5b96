#include "python_tools.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>

#include <climits>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

namespace tigris {

int run_python_tool(int argc, char** argv) {
  if (argc < 2) return -1;
  const std::string tool = argv[1];
  const char* script = tool == "sweep"       ? "tigris_sweep.py"
                       : tool == "reproduce" ? "reproduce.py"
                       : tool == "diff"      ? "tigris_diff.py"
                       : tool == "plot"      ? "tigris_plot.py"
                       : tool == "pipeline-dse" ? "pipeline_dse.py"
                                             : nullptr;
  if (!script) return -1;
  const char* dir_env = std::getenv("TIGRIS_SWEEP_DIR");
  const std::string path = std::string(dir_env && *dir_env ? dir_env : TIGRIS_SWEEP_DIR) + "/" + script;
  if (access(path.c_str(), R_OK) != 0) {
    std::cerr << "tigris: error: tigris " << tool << " needs " << path
              << " (the sweep/ folder of the source tree; set TIGRIS_SWEEP_DIR)\n";
    return 2;
  }
  // The tools call this very binary for every point.
  char self[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n > 0) {
    self[n] = '\0';
    setenv("TIGRIS", self, 1);
  }
  // Debian's python3 carries python3-matplotlib; another one first on PATH may not.
  const std::string python = access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
  std::vector<char*> args = {const_cast<char*>(python.c_str()), const_cast<char*>(path.c_str())};
  for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  execvp(args[0], args.data());
  std::cerr << "tigris: error: cannot run " << python << " " << path << ": " << std::strerror(errno) << '\n';
  return 2;
}

int run_python_script(const std::string& script, const std::vector<std::string>& args, std::string& why) {
  const char* dir_env = std::getenv("TIGRIS_SWEEP_DIR");
  const std::string path = std::string(dir_env && *dir_env ? dir_env : TIGRIS_SWEEP_DIR) + "/" + script;
  if (access(path.c_str(), R_OK) != 0) {
    why = path + " is not there (the sweep/ folder of the source tree; set TIGRIS_SWEEP_DIR)";
    return -1;
  }
  const std::string python = access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
  std::vector<char*> argv = {const_cast<char*>(python.c_str()), const_cast<char*>(path.c_str())};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    why = std::string("cannot start a process: ") + std::strerror(errno);
    return -1;
  }
  if (pid == 0) {
    execvp(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  if (code == 127) why = "cannot run " + python;
  return code;
}

}  // namespace tigris
