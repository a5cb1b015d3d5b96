#include "odometry_command.hpp"
#include "command.hpp"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <utility>

#include <nlohmann/json.hpp>

#include "core/arg_checks.hpp"
#include "core/children.hpp"
#include "core/digest.hpp"
#include "core/out_folder.hpp"
#include "core/slurm_array.hpp"
#include "options.hpp"
#include "python_tools.hpp"
#include "registration/odometry_run.hpp"
#include "registration/search_backends.hpp"
#include "synth_command.hpp"
#include "testbench/presets.hpp"

namespace tigris {
namespace {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

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
      ->check(CLI::IsMember(registration::search_backend_names()));
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
                  registration::odometry_outputs(o.compare),
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
                    registration::odometry_outputs(true),
                    true,
                    {}};
    folder = std::make_unique<OutFolder>(o.out, spec);
  }
  const int code = run_odometry_compare(o);
  folder->finish(code == 0 ? "done" : "failed");
  return code;
}

// The summary on stdout, the plots (a warning when they cannot be drawn), and OUT finished;
// exit 1 when a pair did not converge.
int print_summary(registration::OdometryRun& run, const OdometryOptions& o) {
  const registration::Odometry& odometry = run.odometry();
  odometry.print_summary(stdout, run.metrics(), o.sequence, o.search.empty() ? "exact" : o.search, run.note());
  std::string why;
  const int plotted = run_python_module("odometry-plots", {o.out}, why);
  if (plotted != 0)
    std::fprintf(stderr, "tigris odometry: warning: the plots were not drawn (%s)\n",
                 plotted < 0 || !why.empty()
                     ? why.c_str()
                     : ("python3 -m tigris odometry-plots exit " + std::to_string(plotted)).c_str());
  std::printf("  wrote %s/poses.txt, pairs.csv, metrics.json, trajectory.csv%s (per pair: %s/pairs/)\n", o.out.c_str(),
              plotted == 0 ? ", trajectory.png, errors.png" : "", o.out.c_str());
  const std::size_t not_converged = odometry.totals().not_converged;
  run.folder().finish(not_converged > 0 ? "not converged" : "done");
  return not_converged > 0 ? 1 : 0;
}

}  // namespace

int run_odometry_command(const CLI::App& app, const OdometryOptions& given) {
  OdometryOptions o = given;
  check_odometry_flags(app, o);
  std::unique_ptr<OutFolder> folder;
  const std::vector<std::string> flags = forwarded(o);
  if (o.synthetic > 0) folder = write_synthetic(o, flags);
  if (o.compare) return run_compare(o, flags, std::move(folder));
  registration::OdometrySettings settings;
  settings.sequence = o.sequence;
  settings.frames = o.frames;
  settings.out = o.out;
  settings.flags = flags;
  settings.accel = registration::in_loop(o.search);
  settings.jobs = o.jobs;
  settings.slurm = o.slurm;
  settings.config_inputs = config_inputs(o);
  settings.command_line = o.command_line;
  registration::OdometryRun run(std::move(settings), std::move(folder));
  if (!run.run()) return 0;  // submitted (--no-wait)
  return print_summary(run, o);
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
