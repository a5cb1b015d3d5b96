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
  const char* summary;
};
const Tool kTools[] = {
    {"sweep",
     "Design-space sweep from a JSON spec, locally (--jobs) or as a Slurm job array (--slurm); CSV, JSON and "
     "resume (tigris sweep --help)"},
    {"reproduce", "The paper's section 6 experiments as sweeps, with figures and REPORT.md (tigris reproduce --help)"},
    {"diff",
     "Compare runs (stats.json files, run folders, sweep points): configuration differences, headline figures "
     "side by side with ratios, every other differing leaf (tigris diff --help)"},
    {"plot",
     "Figures of a sweep folder or CSV: headline figures against each swept key, and the paper's figures the "
     "sweep covers (tigris plot --help)"},
    {"pipeline-dse",
     "The paper's section 3: sample the registration pipeline's design space, run each point over a sequence "
     "(locally or on Slurm), Pareto frontiers of error against time, stage and KD-tree shares of the Pareto "
     "points (tigris pipeline-dse --help)"},
};
// Listed in `tigris --help` like every command (no flags of their own there: main() hands their
// words to run_python_tool() before parsing).
const bool kRegistered = [] {
  int order = 60;
  for (const Tool& t : kTools) CommandRegistration({t.name, t.summary, order++, nullptr});
  return true;
}();

// The folder that holds the package tigris: $TIGRIS_PYTHONPATH, else ../python beside this
// binary's bin/ (the build tree), else ../TIGRIS_PYTHON_DIR (an install: lib/python3/dist-packages).
std::string package_parent() {
  const char* dir_env = std::getenv("TIGRIS_PYTHONPATH");
  if (dir_env && *dir_env) return fs::path(dir_env).lexically_normal().string();
  const fs::path prefix = fs::path(self_path()).parent_path().parent_path();
  if (access((prefix / "python" / "tigris" / "__main__.py").c_str(), R_OK) == 0) return (prefix / "python").string();
  return (prefix / TIGRIS_PYTHON_DIR).string();
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

// The command line that runs `python3 -m tigris TOOL ARGS` with the package's parent on
// PYTHONPATH, this binary as $TIGRIS and its commit for the manifests and figure footers. "" with
// `why`.
std::vector<std::string> module_command(const std::string& tool, const std::vector<std::string>& args,
                                        std::string& why) {
  fs::path parent(package_parent());
  if (parent.filename().empty()) parent = parent.parent_path();  // a trailing slash
  if (access((parent / "tigris" / "__main__.py").c_str(), R_OK) != 0) {
    why = (parent / "tigris" / "__main__.py").string() +
          " is not there (the Python package tigris: ../python or ../" TIGRIS_PYTHON_DIR
          " beside the binary's bin/; set TIGRIS_PYTHONPATH to the folder that holds it)";
    return {};
  }
  const std::string python = find_python();
  if (python.empty()) {
    why = "no python3 on PATH";
    return {};
  }
  const char* old = std::getenv("PYTHONPATH");
  setenv("PYTHONPATH", (old && *old ? parent.string() + ":" + old : parent.string()).c_str(), 1);
  const std::string self = self_path();
  if (!self.empty()) setenv("TIGRIS", self.c_str(), 1);  // the tools call this very binary
  setenv("TIGRIS_COMMIT", build_commit(), 1);
  // -P: the working folder does not go first on sys.path (a tigris.py there would shadow us).
  std::vector<std::string> argv{python, "-P", "-m", "tigris", tool};
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}

}  // namespace

int run_python_tool(int argc, char** argv) {
  if (argc < 2) return -1;
  const std::string tool = argv[1];
  if (std::none_of(std::begin(kTools), std::end(kTools), [&](const Tool& t) { return tool == t.name; })) return -1;
  std::string why;
  const std::vector<std::string> command = module_command(tool, {argv + 2, argv + argc}, why);
  if (command.empty()) {
    std::cerr << "tigris: error: tigris " << tool << " needs " << why << '\n';
    return 2;
  }
  std::vector<char*> args;
  for (const std::string& a : command) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  execv(args[0], args.data());
  std::cerr << "tigris: error: cannot run " << command[0] << " -m tigris " << tool << ": " << std::strerror(errno)
            << '\n';
  return 2;
}

int run_python_module(const std::string& tool, const std::vector<std::string>& args, std::string& why) {
  const std::vector<std::string> command = module_command(tool, args, why);
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
