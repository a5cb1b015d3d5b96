#include "python_tools.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "command.hpp"
#include "core/build_info.hpp"
#include "core/children.hpp"
#include "core/share_dir.hpp"

namespace tigris {
namespace {

namespace fs = std::filesystem;

struct Tool {
  const char* name;
  const char* module;
  const char* summary;
};
const Tool kTools[] = {
    {"sweep", "tigris_sweep",
     "Design-space sweep from a JSON spec, locally (--jobs) or as a Slurm job array (--slurm); CSV, JSON and "
     "resume (sweep/tigris_sweep.py; tigris sweep --help)"},
    {"reproduce", "reproduce",
     "The paper's section 6 experiments as sweeps, with figures and REPORT.md (sweep/reproduce.py; tigris "
     "reproduce --help)"},
    {"diff", "tigris_diff",
     "Compare runs (stats.json files, run folders, sweep points): configuration differences, headline figures "
     "side by side with ratios, every other differing leaf (sweep/tigris_diff.py; tigris diff --help)"},
    {"plot", "tigris_plot",
     "Figures of a sweep folder or CSV: headline figures against each swept key, and the paper's figures the "
     "sweep covers (sweep/tigris_plot.py; tigris plot --help)"},
    {"pipeline-dse", "pipeline_dse",
     "The paper's section 3: sample the registration pipeline's design space, run each point over a sequence "
     "(locally or on Slurm), Pareto frontiers of error against time, stage and KD-tree shares of the Pareto "
     "points (sweep/pipeline_dse.py; tigris pipeline-dse --help)"},
};
// Listed in `tigris --help` like every command (no flags of their own there: main() hands their
// words to run_python_tool() before parsing).
const bool kRegistered = [] {
  int order = 60;
  for (const Tool& t : kTools) CommandRegistration({t.name, t.summary, order++, nullptr});
  return true;
}();

// The package folder: TIGRIS_SWEEP_DIR, else ../share/tigris/sweep beside this binary.
std::string package_dir() {
  const char* dir_env = std::getenv("TIGRIS_SWEEP_DIR");
  if (dir_env && *dir_env) return fs::path(dir_env).lexically_normal().string();
  return (fs::path(share_dir()) / "sweep").string();
}

// Debian's python3 carries python3-matplotlib; another one first on PATH may not.
std::string find_python() {
  if (access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
  const char* env_path = std::getenv("PATH");
  const std::string dirs = env_path ? env_path : "";
  for (std::size_t at = 0; at <= dirs.size();) {
    const std::size_t end = std::min(dirs.find(':', at), dirs.size());
    const std::string candidate = dirs.substr(at, end - at) + "/python3";
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
    at = end + 1;
  }
  return "";
}

// The command line that runs `module` of the package, with the package's parent on PYTHONPATH,
// this binary as $TIGRIS and its commit for the manifests and figure footers. "" with `why`.
std::vector<std::string> module_command(const std::string& module, const std::vector<std::string>& args,
                                        std::string& why) {
  fs::path pkg(package_dir());
  if (pkg.filename().empty()) pkg = pkg.parent_path();  // a trailing slash
  if (access((pkg / (module + ".py")).c_str(), R_OK) != 0) {
    why = (pkg / (module + ".py")).string() +
          " is not there (the Python package `sweep`: share/tigris/sweep beside the binary's bin/; "
          "set TIGRIS_SWEEP_DIR)";
    return {};
  }
  const std::string python = find_python();
  if (python.empty()) {
    why = "no python3 on PATH";
    return {};
  }
  const char* old = std::getenv("PYTHONPATH");
  const std::string parent = pkg.parent_path().string();
  setenv("PYTHONPATH", (old && *old ? parent + ":" + old : parent).c_str(), 1);
  const std::string self = self_path();
  if (!self.empty()) setenv("TIGRIS", self.c_str(), 1);  // the tools call this very binary
  setenv("TIGRIS_COMMIT", build_commit(), 1);
  // -P: the working folder does not go first on sys.path (a sweep.py there would shadow us).
  std::vector<std::string> argv{python, "-P", "-m", pkg.filename().string() + "." + module};
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}

}  // namespace

int run_python_tool(int argc, char** argv) {
  if (argc < 2) return -1;
  const std::string tool = argv[1];
  const char* module = nullptr;
  for (const Tool& t : kTools)
    if (tool == t.name) module = t.module;
  if (!module) return -1;
  std::string why;
  const std::vector<std::string> command = module_command(module, {argv + 2, argv + argc}, why);
  if (command.empty()) {
    std::cerr << "tigris: error: tigris " << tool << " needs " << why << '\n';
    return 2;
  }
  std::vector<char*> args;
  for (const std::string& a : command) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  execv(args[0], args.data());
  std::cerr << "tigris: error: cannot run " << command[0] << " -m " << command[3] << ": " << std::strerror(errno)
            << '\n';
  return 2;
}

int run_python_module(const std::string& module, const std::vector<std::string>& args, std::string& why) {
  const std::vector<std::string> command = module_command(module, args, why);
  if (command.empty()) return -1;
  int code = 0;
  try {
    code = wait_child(start_child(command));
  } catch (const std::exception& e) {
    why = e.what();
    return -1;
  }
  if (code == 127) why = "cannot run " + command[0];
  return code;
}

}  // namespace tigris
