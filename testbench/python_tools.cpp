#include "python_tools.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>

#include <climits>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "build_info.hpp"
#include "children.hpp"

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
  setenv("TIGRIS_COMMIT", build_commit(), 1);  // for the manifests and figure footers they write
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
  // start_child runs a path (execv): python3 from PATH is looked up here.
  std::string python = "/usr/bin/python3";
  if (access(python.c_str(), X_OK) != 0) {
    python.clear();
    const char* env_path = std::getenv("PATH");
    std::string dirs = env_path ? env_path : "";
    for (std::size_t at = 0; at <= dirs.size() && python.empty();) {
      const std::size_t end = std::min(dirs.find(':', at), dirs.size());
      const std::string candidate = dirs.substr(at, end - at) + "/python3";
      if (access(candidate.c_str(), X_OK) == 0) python = candidate;
      at = end + 1;
    }
    if (python.empty()) {
      why = "no python3 on PATH";
      return -1;
    }
  }
  setenv("TIGRIS_COMMIT", build_commit(), 1);  // for the figure footers the scripts draw
  std::vector<std::string> argv{python, path};
  argv.insert(argv.end(), args.begin(), args.end());
  int code = 0;
  try {
    code = wait_child(start_child(argv));
  } catch (const std::exception& e) {
    why = e.what();
    return -1;
  }
  if (code == 127) why = "cannot run " + python;
  return code;
}

}  // namespace tigris
