#include "child_batch.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "children.hpp"
#include "timer.hpp"

namespace tigris {
namespace fs = std::filesystem;

namespace {

bool has_result(const ChildBatch& b, std::size_t k) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(b.dir(k) + "/" + b.result, ec));
}

bool run_here(const ChildBatch& b, const std::function<bool(const TaskEnd&)>& ended) {
  run_pool(
      b.count, b.parallel,
      [&](std::size_t k) {
        const std::string dir = b.dir(k);
        fs::create_directories(dir);
        std::vector<std::string> args{b.program};
        for (std::string& a : b.args(k, false)) args.push_back(std::move(a));
        return start_child(args, dir + "/log.txt", "log.txt");
      },
      [&](std::size_t k, int code) {
        return ended({k, code, has_result(b, k), ""});
      });
  return true;
}

bool run_on_slurm(const ChildBatch& b, const std::function<bool(const TaskEnd&)>& ended) {
  // Each task runs exactly the command it runs here, from the program's own path.
  const std::string self =
      b.program == "/proc/self/exe" ? fs::read_symlink(b.program).string() : fs::absolute(b.program).string();
  std::vector<ArrayCommand> commands;
  for (std::size_t k = 0; k < b.count; ++k) {
    const std::string dir = fs::absolute(b.dir(k)).lexically_normal().string();
    fs::create_directories(dir);
    ArrayCommand c;
    c.argv = {self};
    for (std::string& a : b.args(k, true)) c.argv.push_back(std::move(a));
    c.log = dir + "/log.txt";
    c.parent_outputs = "log.txt";
    commands.push_back(c);
  }
  const std::string job = submit_array(b.slurm, commands, b.out, b.name);
  if (b.slurm.no_wait) {
    std::printf("job %s\ncollect when it has ended: rerun the same command (the %s done are reused)\n", job.c_str(),
                b.noun.c_str());
    return false;
  }
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t seen = 0;
  wait_array(job, [&] {
    std::size_t n = 0;
    for (std::size_t k = 0; k < b.count; ++k) n += has_result(b, k);
    if (n != seen)
      std::fprintf(stderr, "%s: Slurm job %s: %zu/%zu %s (%.0f s)\n", b.name.c_str(), job.c_str(), n, b.count,
                   b.noun.c_str(), seconds_since(t0));
    seen = n;
  });
  for (std::size_t k = 0; k < b.count; ++k) ended({k, -1, has_result(b, k), job});
  return true;
}

}  // namespace

bool run_batch(const ChildBatch& b, const std::function<bool(const TaskEnd&)>& ended) {
  if (b.count == 0) return true;
  return b.slurm.slurm ? run_on_slurm(b, ended) : run_here(b, ended);
}

std::string last_log_line(const std::string& dir) {
  std::ifstream f(dir + "/log.txt");
  std::string line, last;
  while (std::getline(f, line))
    if (!line.empty()) last = line;
  return last;
}

}  // namespace tigris
