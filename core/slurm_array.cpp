#include "slurm_array.hpp"

#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include "children.hpp"
#include "json_file.hpp"
#include "out_folder.hpp"  // write_file

namespace tigris {
namespace {

namespace fs = std::filesystem;

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Runs a command line through /bin/sh; its exit code (-1 when its output could not be read
// whole), its stdout in `out` and, when `err` is given, its stderr there (else with stdout).
int capture(const std::vector<std::string>& argv, std::string& out, std::string* err = nullptr) {
  std::string line;
  for (const std::string& a : argv) line += quote(a) + ' ';
  char tmp[] = "/tmp/tigris-slurm-stderr-XXXXXX";
  int fd = -1;
  if (err) {
    fd = ::mkstemp(tmp);
    if (fd < 0) return -1;
    line += "2>" + quote(tmp);
  } else {
    line += "2>&1";
  }
  out.clear();
  int code = -1;
  if (FILE* p = ::popen(line.c_str(), "r")) {
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    const bool whole = !std::ferror(p);
    const int status = ::pclose(p);
    code = !whole ? -1 : WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  }
  if (err) {
    std::ifstream f(tmp);
    *err = std::string(std::istreambuf_iterator<char>(f), {});
    ::close(fd);
    ::unlink(tmp);
  }
  return code;
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

// Tasks not finished yet (any state but a final one): 1 or more, 0 none; -1 when squeue cannot
// tell.
int queued(const std::string& job) {
  std::string out;
  const int code = capture({"squeue", "-h", "-j", job, "-t", "all", "-o", "%i %t"}, out);
  if (code != 0) return code > 0 && out.find("Invalid job id") != std::string::npos ? 0 : -1;
  std::istringstream in(out);
  int n = 0;
  for (std::string id, state; in >> id >> state;)
    n += state != "CD" && state != "CA" && state != "F" && state != "TO" && state != "NF" && state != "PR" &&
         state != "OOM" && state != "BF" && state != "DL";
  return n;
}

}  // namespace

void add_slurm_options(CLI::App& app, SlurmOptions& o) {
  CLI::Option* s =
      app.add_flag("--slurm", o.slurm, "Run the pairs as one Slurm job array (sbatch) instead of local processes");
  app.add_option("--partition", o.partition, "With --slurm: sbatch --partition")->needs(s);
  app.add_option("--time", o.time, "With --slurm: sbatch --time (per array task)")->needs(s);
  app.add_option("--mem", o.mem, "With --slurm: sbatch --mem (per array task)")->needs(s);
  app.add_option("--chunk", o.chunk, "With --slurm: pairs per array task")
      ->check(CLI::Range(1, 100000))
      ->needs(s)
      ->capture_default_str();
  app.add_option("--sbatch-arg", o.sbatch_args,
                 "With --slurm: one more raw sbatch argument, repeatable (--sbatch-arg=--qos=low)")
      ->needs(s)
      ->allow_extra_args(false);
  app.add_flag("--no-wait", o.no_wait, "With --slurm: return after submitting; rerun the same command to collect")
      ->needs(s);
}

std::string submit_array(const SlurmOptions& o, const std::vector<ArrayCommand>& commands, const std::string& dir,
                         const std::string& name) {
  const std::string sdir = fs::absolute(dir + "/slurm").lexically_normal().string();
  fs::create_directories(sdir);
  char stamp[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::localtime(&now));
  const std::string script = sdir + "/array-" + stamp + "-" + std::to_string(::getpid()) + ".sh";
  const std::size_t tasks =
      (commands.size() + static_cast<std::size_t>(o.chunk) - 1) / static_cast<std::size_t>(o.chunk);
  write_file(script, [&](std::ostream& f) {
    f << "#!/bin/sh\n# One task of a " << name << " job array: runs its chunk of commands, each logged on its own.\n"
      << "status=0\ncase \"$SLURM_ARRAY_TASK_ID\" in\n";
    for (std::size_t t = 0; t < tasks; ++t) {
      f << t << ")\n";
      for (std::size_t k = t * o.chunk; k < std::min(commands.size(), (t + 1) * o.chunk); ++k) {
        f << " ";
        if (!commands[k].parent_outputs.empty()) f << " TIGRIS_PARENT_OUTPUTS=" << quote(commands[k].parent_outputs);
        for (const std::string& a : commands[k].argv) f << ' ' << quote(a);
        f << " > " << quote(commands[k].log) << " 2>&1 || status=$?\n";
      }
      f << " ;;\n";
    }
    f << "*) echo \"no task $SLURM_ARRAY_TASK_ID in this array\" >&2; exit 2 ;;\nesac\nexit $status\n";
  });
  fs::permissions(script, fs::perms::owner_exec | fs::perms::group_exec, fs::perm_options::add);
  std::string log_dir;  // sbatch reads % in --output as a pattern: %% is a literal one
  for (char c : sdir) log_dir += c == '%' ? std::string("%%") : std::string(1, c);
  std::vector<std::string> cmd{"sbatch",
                               "--parsable",
                               "--array=0-" + std::to_string(tasks - 1),
                               "--job-name=" + name,
                               "--output=" + log_dir + "/%A_%a.out",
                               "--chdir=" + fs::absolute(dir).lexically_normal().string()};
  if (!o.partition.empty()) cmd.push_back("--partition=" + o.partition);
  if (!o.time.empty()) cmd.push_back("--time=" + o.time);
  if (!o.mem.empty()) cmd.push_back("--mem=" + o.mem);
  cmd.insert(cmd.end(), o.sbatch_args.begin(), o.sbatch_args.end());
  cmd.push_back(script);
  std::string out, err;
  std::string shown;
  for (const std::string& a : cmd) shown += (shown.empty() ? "" : " ") + quote(a);
  const int code = capture(cmd, out, &err);
  if (code == 127 && err.find("not found") != std::string::npos)
    throw SlurmError("--slurm: sbatch not found on PATH (is Slurm installed and SLURM_CONF set?)");
  if (code != 0)
    throw SlurmError("sbatch failed (exit " + std::to_string(code) + "): " + trimmed(err + out) +
                     "\n  command: " + shown);
  // --parsable prints "jobid[;cluster]" as its last line of stdout; warnings go to stderr.
  std::string last = trimmed(out);
  last = last.substr(last.find_last_of('\n') == std::string::npos ? 0 : last.find_last_of('\n') + 1);
  const std::string job = last.substr(0, last.find(';'));
  if (job.empty() || job.find_first_not_of("0123456789") != std::string::npos)
    throw SlurmError("sbatch printed no job id (stdout: '" + trimmed(out) + "', stderr: '" + trimmed(err) +
                     "')\n  command: " + shown);
  if (!trimmed(err).empty()) std::fprintf(stderr, "tigris: sbatch said: %s\n", trimmed(err).c_str());
  nlohmann::ordered_json j{
      {"job", job}, {"script", script}, {"tasks", tasks}, {"commands", commands.size()}, {"command", cmd}};
  write_file(sdir + "/job.json", [&](std::ostream& f) { f << j.dump(2) << '\n'; });
  std::fprintf(stderr, "tigris: submitted Slurm job array %s: %zu task(s) for %zu command(s); logs %s/%s_<task>.out\n",
               job.c_str(), tasks, commands.size(), sdir.c_str(), job.c_str());
  return job;
}

void wait_array(const std::string& job, const std::function<void()>& tick) {
  const DeferStop defer;  // a stop signal cancels the array here, then ends the command
  int misses = 0;
  while (true) {
    const int active = queued(job);  // asked before the tick: no result is missed
    tick();
    if (const int sig = stop_signal()) {
      std::string out;
      capture({"scancel", job}, out);
      std::fprintf(stderr, "tigris: cancelled Slurm job %s; the pairs finished are kept, a rerun resumes\n",
                   job.c_str());
      throw Interrupted(sig);
    }
    if (active == 0) break;
    misses = active < 0 ? misses + 1 : 0;
    if (misses > 60) throw std::runtime_error("squeue cannot report Slurm job " + job + " (60 tries)");
    for (int i = 0; i < 10 && !stop_signal(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

std::string active_array(const std::string& dir) {
  const std::string path = dir + "/slurm/job.json";
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::symlink_status(path, ec))) return "";
  const nlohmann::json j = parse_json_text(read_input(path, "the Slurm job record", kMaxSettingsBytes), path);
  const std::string job = j.value("job", std::string());
  return !job.empty() && queued(job) > 0 ? job : "";
}

}  // namespace tigris
