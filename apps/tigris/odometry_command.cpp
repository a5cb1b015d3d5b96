#include "odometry_command.hpp"
#include "command.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <Eigen/LU>
#include <nlohmann/json.hpp>

#include "core/arg_checks.hpp"
#include "core/child_batch.hpp"
#include "core/children.hpp"
#include "core/flag_values.hpp"
#include "core/json_file.hpp"
#include "core/out_folder.hpp"
#include "core/slurm_array.hpp"
#include "core/timer.hpp"
#include "options.hpp"
#include "python_tools.hpp"
#include "registration/odometry.hpp"
#include "registration/odometry_metrics.hpp"
#include "registration/report.hpp"
#include "synth_command.hpp"
#include "testbench/presets.hpp"
#include "testbench/report.hpp"
#include "testbench/run_inputs.hpp"
#include "workloads/kitti_sequence.hpp"
#include "workloads/pose.hpp"

namespace tigris {
namespace {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

std::string frame_tag(std::size_t i) {
  char b[16];
  std::snprintf(b, sizeof b, "%06zu", i);
  return b;
}

// The flags every pair's `tigris register` gets, in a fixed order (also the resume key).
std::vector<std::string> forwarded(const OdometryOptions& o) {
  std::vector<std::string> a{"--preset", o.preset};
  if (!o.config.empty()) a.insert(a.end(), {"--config", fs::absolute(o.config).string()});
  for (const std::string& s : o.sets) a.insert(a.end(), {"--set", s});
  if (!o.search.empty()) a.insert(a.end(), {"--search", o.search});
  if (!o.height.empty()) a.insert(a.end(), {"--height", o.height});
  if (!o.approx_thd.empty()) a.insert(a.end(), {"--approx-thd", o.approx_thd});
  if (!o.accel_config.empty()) a.insert(a.end(), {"--accel-config", fs::absolute(o.accel_config).string()});
  for (const std::string& s : o.accel_sets) a.insert(a.end(), {"--accel-set", s});
  char w[32];
  std::snprintf(w, sizeof w, "%.17g", o.max_work);
  a.insert(a.end(), {"--max-work", w});
  return a;
}

void check_register_flags(const OdometryOptions& o) {
  std::vector<std::string> args{"/proc/self/exe", "register"};
  for (const std::string& a : forwarded(o)) args.push_back(a);
  args.push_back("--check-flags");
  if (wait_child(start_child(args)) != 0)
    throw std::invalid_argument("the flags tigris odometry gives each pair's tigris register do not hold" +
                                (o.search.empty() ? std::string() : " (--search " + o.search + ")") +
                                ": its message is above; nothing was run or written");
}

nlohmann::json config_inputs(const OdometryOptions& o) {
  nlohmann::json in = nlohmann::json::array();
  if (!o.config.empty()) in.push_back(input_file("config", o.config));
  if (!o.accel_config.empty()) in.push_back(input_file("accelerator config", o.accel_config));
  return in;
}

std::vector<std::string> odometry_outputs(bool compare) {
  if (compare)
    return {"comparison.json", "flann/",          "exact/",          "approx/",         "accel/",
            "sequence/",       "flann-repeat-*/", "exact-repeat-*/", "approx-repeat-*/"};
  return {"poses.txt",  "trajectory.csv", "pairs.csv", "metrics.json", "trajectory.png",
          "errors.png", "pairs/",         "slurm/",    "sequence/"};
}

// A pair's registration.json: false when it is not there (the pair runs); a report that is
// there but not whole (edited, truncated; in the loop, without the accelerator's figures) is an
// error naming the file and the key.
bool read_pair(const std::string& path, bool accel, registration::Report& out) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec))) return false;
  const std::string again = " (remove the pair's folder to register it again)";
  try {
    out = registration::read_report(path);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(e.what() + again);
  }
  if (accel && !out.in_loop())
    throw std::invalid_argument(
        path + ": no 'accelerator', which --search accel* writes; not a whole tigris register " + "report" + again);
  return true;
}

}  // namespace

void add_odometry_options(CLI::App& app, OdometryOptions& o) {
  CLI::Option* seq = input_flag(
      app.add_option("--sequence", o.sequence,
                     "KITTI-layout folder: velodyne/NNNNNN.bin, optional poses.txt (ground truth) and calib.txt (Tr)"));
  CLI::Option* syn =
      app.add_option("--synthetic", o.synthetic,
                     "Instead of --sequence: a synthetic drive of N frames with exact poses (tigris synth), "
                     "written to OUT/sequence first")
          ->check(CLI::Range(2, 20000));
  seq->excludes(syn);
  app.add_option("--seed", o.seed, "With --synthetic: the drive's seed (0 .. 2^64-1)")
      ->check(uint64_text())
      ->needs(syn)
      ->capture_default_str();
  app.add_option("--frames", o.frames, "A:B, the first and the last frame (default: every frame)");
  app.add_option("--jobs", o.jobs, "Pairs registered at once, each a process of its own")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  app.add_option("--preset", o.preset, "Pipeline preset: dp4 or dp7 (as tigris register)")
      ->check(CLI::IsMember({"dp4", "dp7"}))
      ->capture_default_str();
  input_flag(app.add_option("--config", o.config, "Pipeline configuration JSON (as tigris register)"));
  app.add_option("--set", o.sets, "Set one pipeline key (repeatable, as tigris register)")->allow_extra_args(false);
  app.add_option("--search", o.search, "3D KD-tree back-end: flann, exact, approx, accel or accel-approx")
      ->check(CLI::IsMember({"flann", "exact", "approx", "accel", "accel-approx"}));
  app.add_option("--height", o.height, "Top-tree height 0..30 or 'full' (as tigris register)");
  app.add_option("--approx-thd", o.approx_thd, "Approximate NN threshold in metres (as tigris register)");
  input_flag(app.add_option("--accel-config", o.accel_config,
                            "With --search accel*: the accelerator's configuration, a preset's name or a JSON file"))
      ->transform(preset_or_file());
  app.add_option("--accel-set", o.accel_sets, "With --search accel*: set one accelerator key (repeatable)")
      ->allow_extra_args(false);
  app.add_option("--max-work", o.max_work, "Work bound of each pair's registration (as tigris register)")
      ->check(finite_range(0.0, 1e18))
      ->capture_default_str();
  app.add_option("--out", o.out, "Output folder")->capture_default_str();
  add_slurm_options(app, o.slurm);
  app.add_flag("--compare", o.compare,
               "Register the sequence with flann, exact, approx and accel, each into OUT/<back-end>/, then one table: "
               "KD-tree and end-to-end time against FLANN, energy, KITTI errors (OUT/comparison.json)");
  app.add_option("--repeat", o.repeat,
                 "With --compare: run each CPU back-end (flann, exact, approx) this many times, interleaved, and "
                 "report the median time with min and max; the accelerator's run is modeled and runs once")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
}

namespace {

// Refuses flags that do not go together, before anything is written.
void check_odometry_flags(const CLI::App& app, const OdometryOptions& o) {
  if (o.sequence.empty() && o.synthetic == 0)
    throw std::invalid_argument("give --sequence DIR (a KITTI-layout folder) or --synthetic N (a synthetic drive)");
  if (!o.compare && app.count("--repeat"))
    throw std::invalid_argument("--repeat goes with --compare (it times the CPU back-ends of the comparison)");
  if (o.compare)
    for (const char* flag : {"--search", "--no-wait"})
      if (app.count(flag))
        throw std::invalid_argument(std::string(flag) +
                                    " does not go with --compare (it runs flann, exact, approx and "
                                    "accel one after the other)");
  // Every flag the pairs get is checked by `tigris register` itself before anything is written.
  if (o.compare)
    for (const OdometryOptions& b : compare_variants(o)) check_register_flags(b);
  else
    check_register_flags(o);
}

// --synthetic: claims OUT and writes the drive to OUT/sequence, which then is the sequence (o.sequence).
std::unique_ptr<OutFolder> write_synthetic(OdometryOptions& o, const std::vector<std::string>& flags) {
  // The drive is an output (OUT/sequence, written by the synth core): the settings decide it.
  FolderSpec spec{"odometry",
                  {},
                  nlohmann::json({{"synthetic", o.synthetic},
                                  {"seed", o.seed},
                                  {"frames", o.frames},
                                  {"register_flags", flags},
                                  {"compare", o.compare}}),
                  config_inputs(o),
                  odometry_outputs(o.compare),
                  true,
                  {}};
  auto folder = std::make_unique<OutFolder>(o.out, spec);
  DriveConfig drive;
  drive.frames = o.synthetic;
  drive.seed = o.seed;
  o.sequence = o.out + "/sequence";
  std::fprintf(stderr, "tigris odometry: the synthetic drive (seed %llu, %d frames) in %s\n",
               static_cast<unsigned long long>(o.seed), o.synthetic, o.sequence.c_str());
  write_synthetic_drive(drive, o.sequence, o.jobs, false);
  return folder;
}

// --compare: claims OUT (unless the synthetic drive did) and runs each back-end's odometry into it.
int run_compare(const OdometryOptions& o, const std::vector<std::string>& flags, std::unique_ptr<OutFolder> folder) {
  if (!folder) {  // each back-end's odometry checks (and records) the sequence's files itself
    FolderSpec spec{"odometry",
                    {},
                    nlohmann::json({{"sequence", fs::absolute(o.sequence).lexically_normal().string()},
                                    {"frames", o.frames},
                                    {"register_flags", flags},
                                    {"compare", true}}),
                    config_inputs(o),
                    odometry_outputs(true),
                    true,
                    {}};
    folder = std::make_unique<OutFolder>(o.out, spec);
  }
  const int code = run_odometry_compare(o);
  folder->finish(code == 0 ? "done" : "failed");
  return code;
}

// One odometry of one back-end, its steps in the order run() takes them; the members are what
// one step leaves for the next.
struct OdometryRun {
  OdometryOptions o;
  std::vector<std::string> flags;     // each pair's `tigris register` flags
  std::unique_ptr<OutFolder> folder;  // null until claimed (the synthetic drive claims it first)
  KittiSequence seq;
  std::size_t first = 0, last = 0, pairs = 0;        // the frames registered, pairs = last - first
  std::vector<registration::Report> regs;            // each pair's registration.json
  std::vector<std::size_t> todo;                     // the pairs still to register
  bool accel = false;                                // --search accel*: the accelerator's modeled figures too
  std::unique_ptr<registration::Odometry> odometry;  // chained, once every pair is registered

  OdometryRun(OdometryOptions options, std::vector<std::string> pair_flags, std::unique_ptr<OutFolder> claimed)
      : o(std::move(options)), flags(std::move(pair_flags)), folder(std::move(claimed)),
        accel(o.search == "accel" || o.search == "accel-approx") {}
  int run();
  void read_sequence();
  void claim_folder();
  void plan_pairs();
  bool run_pairs();
  int write_files();
  int print_summary(const ordered_json& m, const std::string& note);
};

int OdometryRun::run() {
  read_sequence();
  claim_folder();
  plan_pairs();
  if (!run_pairs()) return 0;
  odometry = std::make_unique<registration::Odometry>(first, std::move(regs), seq.poses, accel);
  return write_files();
}

// The sequence's listing, poses and calibration, and the frames to register.
void OdometryRun::read_sequence() {
  seq = read_kitti_sequence(o.sequence);
  if (seq.scans.size() < 2) throw std::invalid_argument(o.sequence + ": a sequence needs two frames or more");
  std::tie(first, last) = parse_frame_range(o.frames, seq.scans.size());
}

// Claims OUT for a sequence given with --sequence, keyed on every input the pairs read.
void OdometryRun::claim_folder() {
  if (!folder) {
    // A rerun resumes only with the same flags, frames and file contents (every scan of the
    // range, poses.txt and calib.txt included): changed inputs never mix with old pairs.
    nlohmann::json inputs = config_inputs(o);
    for (std::size_t i = first; i <= last; ++i) inputs.push_back(input_file("scan " + frame_tag(i), seq.scans[i]));
    for (const char* name : {"poses.txt", "calib.txt"}) {
      const std::string path = o.sequence + "/" + name;
      std::error_code ec;
      if (fs::exists(fs::symlink_status(path, ec))) inputs.push_back(input_file(name, path));
    }
    FolderSpec spec{"odometry",
                    {},
                    nlohmann::json({{"sequence", fs::absolute(o.sequence).lexically_normal().string()},
                                    {"frames", {first, last}},
                                    {"register_flags", flags}}),
                    inputs,
                    odometry_outputs(false),
                    true,
                    {}};
    folder = std::make_unique<OutFolder>(o.out, spec);
  }
  fs::create_directories(o.out + "/pairs");
}

// Reads the pairs a run before left in OUT/pairs (a rerun resumes) and lists the rest.
void OdometryRun::plan_pairs() {
  // Each pair: frame i + 1 (source) into frame i (target), in OUT/pairs/<i>/.
  pairs = last - first;
  regs.resize(pairs);
  for (std::size_t k = 0; k < pairs; ++k)
    if (!read_pair(o.out + "/pairs/" + frame_tag(first + k) + "/registration.json", accel, regs[k])) todo.push_back(k);
  if (!seq.note.empty()) std::fprintf(stderr, "tigris odometry: note: %s\n", seq.note.c_str());
  std::fprintf(stderr, "tigris odometry: %s, frames %zu..%zu: %zu pairs (%zu already in %s), --jobs %d\n",
               o.sequence.c_str(), first, last, pairs, pairs - todo.size(), o.out.c_str(), o.jobs);
  if (const std::string job = active_array(o.out); !job.empty())
    throw std::invalid_argument("Slurm job " + job + " of an earlier submission still runs into " + o.out +
                                ": wait for it (squeue -j " + job + ") or cancel it (scancel " + job + ")");
}

// Registers the pairs to do, each a `tigris register` in OUT/pairs/<target frame>/, here or
// as one Slurm array; false: submitted with --no-wait (OUT is finished).
bool OdometryRun::run_pairs() {
  ChildBatch batch;
  batch.count = todo.size();
  batch.dir = [&](std::size_t i) { return o.out + "/pairs/" + frame_tag(first + todo[i]); };
  batch.result = "registration.json";
  batch.args = [&](std::size_t i, bool on_slurm) {
    const std::size_t k = todo[i];
    const auto path = [&](const std::string& p) { return on_slurm ? fs::absolute(p).string() : p; };
    std::vector<std::string> args{"register", "--source", path(seq.scans[first + k + 1]), "--target",
                                  path(seq.scans[first + k])};
    args.insert(args.end(), flags.begin(), flags.end());
    if (!on_slurm && o.jobs > 1) args.insert(args.end(), {"--jobs", "1"});  // the pairs share the cores already
    const std::string dir = batch.dir(i);
    args.insert(args.end(), {"--out", on_slurm ? fs::absolute(dir).lexically_normal().string() : dir});
    return args;
  };
  batch.parallel = o.jobs;
  batch.slurm = o.slurm;
  batch.out = o.out;
  batch.name = "tigris-odometry";
  batch.noun = "pairs";
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t done = 0;
  std::string failure;
  const bool waited = run_batch(batch, [&](const TaskEnd& e) {
    const std::size_t k = todo[e.k];
    const std::string dir = batch.dir(e.k), pair = frame_tag(first + k + 1) + " -> " + frame_tag(first + k);
    const bool ok =
        (e.code == 0 || e.code == 1 || !e.job.empty()) && read_pair(dir + "/" + batch.result, accel, regs[k]);
    if (e.job.empty()) {  // here: a line a pair as it ends
      const double elapsed = seconds_since(t0);
      ++done;
      std::fprintf(stderr, "tigris odometry: pair %zu/%zu (%s): %s (%.0f s elapsed, about %.0f s left)\n", done,
                   todo.size(), pair.c_str(), ok ? regs[k].result.status.c_str() : "FAILED", elapsed,
                   elapsed / static_cast<double>(done) * static_cast<double>(todo.size() - done));
    }
    if (!ok && failure.empty())
      failure = "pair " + pair + ": " +
                (e.job.empty() ? "tigris register exited " + std::to_string(e.code) + " (" + dir +
                                     "/log.txt: " + last_log_line(dir) + ")"
                               : "no result from Slurm job " + e.job + " (" + dir + "/log.txt: " + last_log_line(dir) +
                                     "; task logs in " + o.out + "/slurm/)");
    return failure.empty();  // here, a failure stops the scheduling
  });
  if (!waited) {
    folder->finish("submitted");
    return false;
  }
  if (!failure.empty()) throw std::invalid_argument(failure + "; the pairs done are kept, a rerun resumes");
  return true;
}

// OUT/poses.txt, trajectory.csv, pairs.csv and metrics.json; then the summary.
int OdometryRun::write_files() {
  const registration::Odometry& odo = *odometry;
  write_file(o.out + "/poses.txt", [&](std::ostream& f) { write_kitti_poses(f, odo.estimated(), seq.velo_to_cam); });
  write_file(o.out + "/trajectory.csv", [&](std::ostream& f) { odo.write_trajectory_csv(f); });
  write_file(o.out + "/pairs.csv", [&](std::ostream& f) { odo.write_pairs_csv(f); });
  ordered_json m;
  m["command"] = "odometry";
  m["command_line"] = o.command_line;
  m["sequence"] = o.sequence;
  m["calibration"] = seq.calibration;
  // A drive tigris synth wrote has exact poses: equal steps there are steady driving.
  const bool synthetic = fs::exists(o.sequence + "/drive.json");
  m["ground_truth_source"] = seq.poses.empty() ? "none"
                             : synthetic       ? "exact (a synthetic drive, tigris synth: drive.json)"
                                               : "poses.txt";
  if (!seq.note.empty()) m["sequence_note"] = seq.note;
  m["frames"] = {first, last};
  m["pairs"] = pairs;
  m["register_flags"] = flags;
  const std::string note = odo.add_metrics(m, synthetic);
  write_file(o.out + "/metrics.json",
             [&](std::ostream& f) { f << m.dump(2, ' ', false, ordered_json::error_handler_t::replace) << '\n'; });
  return print_summary(m, note);
}

// The summary on stdout, the plots (a warning when they cannot be drawn), and OUT finished;
// exit 1 when a pair did not converge.
int OdometryRun::print_summary(const ordered_json& m, const std::string& note) {
  const registration::Odometry::Totals& sum = odometry->totals();
  odometry->print_summary(stdout, m, o.sequence, o.search.empty() ? "exact" : o.search, note);
  std::string why;
  const int plotted = run_python_module("odometry_plots", {o.out}, why);
  if (plotted != 0)
    std::fprintf(stderr, "tigris odometry: warning: the plots were not drawn (%s)\n",
                 plotted < 0 || !why.empty()
                     ? why.c_str()
                     : ("python3 -m sweep.odometry_plots exit " + std::to_string(plotted)).c_str());
  std::printf("  wrote %s/poses.txt, pairs.csv, metrics.json, trajectory.csv%s (per pair: %s/pairs/)\n", o.out.c_str(),
              plotted == 0 ? ", trajectory.png, errors.png" : "", o.out.c_str());
  folder->finish(sum.not_converged > 0 ? "not converged" : "done");
  return sum.not_converged > 0 ? 1 : 0;
}

}  // namespace

int run_odometry_command(const CLI::App& app, const OdometryOptions& given) {
  OdometryOptions o = given;
  check_odometry_flags(app, o);
  std::unique_ptr<OutFolder> folder;
  const std::vector<std::string> flags = forwarded(o);
  if (o.synthetic > 0) folder = write_synthetic(o, flags);
  if (o.compare) return run_compare(o, flags, std::move(folder));
  OdometryRun odometry(std::move(o), flags, std::move(folder));
  return odometry.run();
}

namespace {

const CommandRegistration kRegistration{options_command<OdometryOptions>(
    "odometry",
    "Register each frame of a KITTI-layout sequence into the previous one (tigris register per "
    "pair, --jobs at a time), chain the poses, KITTI's error metrics",
    40, [](CLI::App& app, OdometryOptions& o) { add_odometry_options(app, o); },
    [](const CLI::App& app, OdometryOptions& o, const CommandLine& line) {
      o.command_line = line.text;
      o.argv = line.argv;
      return run_odometry_command(app, o);
    })};

}  // namespace
}  // namespace tigris
