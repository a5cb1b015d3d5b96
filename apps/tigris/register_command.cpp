#include "register_command.hpp"
#include "command.hpp"

#include <cstdio>
#include <iostream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "core/arg_checks.hpp"
#include "core/digest.hpp"
#include "core/out_folder.hpp"
#include "options.hpp"
#include "registration/pipeline_flags.hpp"
#include "registration/register_run.hpp"
#include "registration/report.hpp"
#include "registration/report_summary.hpp"
#include "registration/search_backends.hpp"
#include "testbench/accel_in_loop.hpp"
#include "testbench/config.hpp"
#include "testbench/presets.hpp"
#include "testbench/sampling.hpp"
#include "testbench/simulation.hpp"
#include "workloads/frame_pair.hpp"

namespace tigris {
namespace {

using nlohmann::ordered_json;

}  // namespace

void add_register_options(CLI::App& app, RegisterOptions& o) {
  input_flag(app.add_option("--source", o.source,
                            "Source (later) frame: KITTI .bin, .pcd or .ply (default: synthetic frame 1)"));
  input_flag(app.add_option("--target", o.target, "Target (earlier) frame, same formats (default: synthetic frame 0)"));
  app.add_option("--seed", o.seed, "Seed of the built-in synthetic pair (0 .. 2^64-1)")
      ->capture_default_str()
      ->check(uint64_text());
  app.add_option("--preset", o.preset, "Pipeline preset: dp4 (performance) or dp7 (accuracy)")
      ->check(CLI::IsMember({"dp4", "dp7"}))
      ->capture_default_str();
  input_flag(app.add_option("--config", o.config, "Pipeline configuration JSON applied over the preset"));
  app.add_option("--set", o.sets, "Set one key, e.g. --set icp.max_iterations=30 (repeatable)")
      ->allow_extra_args(false);
  app.add_option("--search", o.search,
                 "3D KD-tree back-end: flann (PCL's, the CPU baseline), exact or approx (golden "
                 "model on the CPU), accel or accel-approx (the accelerator model in the loop: each "
                 "stage's query set runs as one simulated job, checked against the golden model); "
                 "default: search.backend (exact)")
      ->check(CLI::IsMember(registration::search_backend_names()));
  app.add_option("--height", o.height, "Top-tree height 0..30 or 'full' (default: search.top_height, 10)");
  app.add_option("--approx-thd", o.approx_thd,
                 "Approximate NN threshold in metres (sets search.nn_thd; search.radius_thd becomes "
                 "0.4 * T / 1.2 of r, so 1.2 gives the paper's pair and 0 exact search); implies "
                 "--search approx");
  app.add_option("--inject-kth", o.inject_kth,
                 "Error injection (paper Fig. 5): RPCE's nearest-neighbour searches (both ways when "
                 "reciprocal) return the K-th nearest neighbour; 1: no error (sets inject.rpce_kth)");
  app.add_option("--inject-shell", o.inject_shell,
                 "Error injection: normal estimation's radius searches return the points with "
                 "R1 <= d <= R2 instead of d <= r, R1 < r < R2 (r = normals.radius; sets "
                 "inject.normals_shell_inner/_outer)");
  input_flag(app.add_option("--ground-truth", o.ground_truth,
                            "Ground truth target <- source: a 4x4 or KITTI-style 3x4 row-major text file"));
  input_flag(app.add_option("--kitti-poses", o.kitti_poses,
                            "Ground truth from a KITTI poses.txt (camera frame, converted to the Velodyne frame)"));
  app.add_option("--kitti-frames", o.kitti_frames, "SOURCE,TARGET pose lines of --kitti-poses")->capture_default_str();
  app.add_option("--max-work", o.max_work,
                 "Stop the registration when its KD-tree searches have computed and returned more than "
                 "this many distances and neighbours (a KITTI pair takes 4e8 with dp4, 1.3e9 with dp7); 0: no limit")
      ->check(finite_range(0.0, 1e18))
      ->capture_default_str();
  output_flag(app.add_option("--record-trace", o.record_trace,
                             "Record every 3D KD-tree search as a workload trace (jobs, clouds, results, CPU seconds; "
                             "traces/README.md) for tigris run --trace"));
  input_flag(
      app.add_option("--accel-config", o.accel_config,
                     "With --search accel*: the accelerator's configuration, a preset's name or a JSON file (as tigris "
                     "run --config; default: the built-in paper configuration)"))
      ->transform(preset_or_file());
  app.add_option("--accel-set", o.accel_sets,
                 "With --search accel*: set one accelerator key, e.g. --accel-set be.search_units=64 "
                 "(repeatable; tigris run --list-config lists them); sim.sampling is auto here (jobs long enough "
                 "are sampled, docs/sampling.md): --accel-set sim.sampling=off simulates every query")
      ->allow_extra_args(false);
  app.add_option("--jobs", o.jobs,
                 "With --search accel*: accelerator jobs simulated at a time. 2: a stage's independent jobs (the "
                 "source's and the target's outlier removal and normals) run side by side; 1: one at a time; default: "
                 "2 on a machine with two or more cores. Results, figures and the recorded trace do not depend on it")
      ->check(CLI::Range(1, 2));
  app.add_flag("--compare", o.compare,
               "Run the registration four times, each in a process of its own: on the CPU with PCL's FLANN "
               "and with the golden model, on the accelerator exact and approximate; print one table "
               "(KD-tree time, end to end, KD-tree energy, error) and write OUT/comparison.json");
  app.add_option("--repeat", o.repeat,
                 "With --compare: time each CPU back-end (flann, exact) this many times, interleaved, and report "
                 "the median with min and max; the accelerator's rows are modeled and run once")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_flag("--list-config", o.list_config, "Print every configuration key of the preset and exit");
  app.add_flag("--list-stages", o.list_stages,
               "Print the pipeline's stages in order as JSON (registration.json's key, the paper's title, the "
               "paper's parts of a stage), for tools, and exit");
  app.add_flag("--json", o.json,
               "With --list-config: print the keys as JSON (type, default, range or names, "
               "meaning), for tools");
  app.add_option("--out", o.out, "Output folder for registration.json")->capture_default_str();
  app.add_flag("--check-flags", o.check_flags,
               "Check every flag and configuration, then exit 0 without reading a file or running "
               "(odometry and --compare check the flags they forward this way)");
}

nlohmann::json register_inputs(const RegisterOptions& o) {
  nlohmann::json inputs = nlohmann::json::array();
  for (const auto& [role, path] : {std::pair<const char*, std::string>{"source", o.source},
                                   {"target", o.target},
                                   {"config", o.config},
                                   {"ground truth", o.ground_truth},
                                   {"KITTI poses", o.kitti_poses},
                                   {"accelerator config", o.accel_config}})
    if (!path.empty()) inputs.push_back(input_file(role, path));
  return inputs;
}

namespace {

// The pipeline's configuration from the preset, --config, --set and the flags over them.
registration::PipelineConfig pipeline_config(const RegisterOptions& o, bool in_loop) {
  if (!in_loop && (!o.accel_config.empty() || !o.accel_sets.empty()))
    throw std::invalid_argument(std::string(o.accel_config.empty() ? "--accel-set" : "--accel-config") +
                                " configures the accelerator in the loop: it needs --search accel or accel-approx");
  if (in_loop && !o.record_trace.empty())
    throw std::invalid_argument(
        "--record-trace records the CPU's searches: use --search flann, exact or approx "
        "(then tigris run --trace replays them on the accelerator)");
  return registration::config_from_flags(
      {o.preset, o.config, o.sets, o.search, o.height, o.approx_thd, o.inject_kth, o.inject_shell});
}

// The flags that only go together, and the accelerator's configuration (checked before any work).
hw::AcceleratorConfig check_register_flags(const CLI::App& app, const RegisterOptions& o, bool in_loop) {
  if (app.count("--source") != app.count("--target"))
    throw std::invalid_argument("--source and --target go together (neither: the built-in synthetic pair)");
  if (!o.ground_truth.empty() && !o.kitti_poses.empty())
    throw std::invalid_argument("give --ground-truth or --kitti-poses, not both");
  if (app.count("--kitti-frames") && o.kitti_poses.empty())
    throw std::invalid_argument("--kitti-frames " + o.kitti_frames +
                                " picks lines of --kitti-poses, which is not given");
  // The accelerator in the loop: its configuration checked before any work.
  hw::AcceleratorConfig accel_cfg;
  // Sampled where a job is long enough to gain (docs/sampling.md); --accel-set sim.sampling=off
  // simulates every query.
  accel_cfg.sim.sampling = hw::AcceleratorConfig::Sim::kAuto;
  if (!o.accel_config.empty()) apply_config_file(accel_cfg, o.accel_config);
  for (const std::string& s : o.accel_sets) apply_setting(accel_cfg, s, "--accel-set '" + s + "'");
  if (in_loop) validate_config(accel_cfg);
  check_distinct_paths(
      {{"--source", o.source},
       {"--target", o.target},
       {"--config", o.config},
       {"--ground-truth", o.ground_truth},
       {"--kitti-poses", o.kitti_poses},
       {"--accel-config", o.accel_config}},
      {{"--out (registration.json)", o.out + "/registration.json"}, {"--record-trace", o.record_trace}});
  return accel_cfg;
}

FramePairSpec frame_spec(const RegisterOptions& o) {
  return {o.source, o.target, o.seed, o.ground_truth, o.kitti_poses, o.kitti_frames};
}

// The typed report of the registration (registration/report.hpp writes registration.json).
registration::Report make_report(const RegisterOptions& o, const registration::PipelineConfig& config, bool in_loop,
                                 const FramePair& f, const registration::RegistrationResult& r, double work_spent,
                                 const hw::AcceleratorConfig& accel_cfg, const ordered_json& accel_jobs) {
  registration::Report rep;
  rep.source = {f.source_name, f.source.size()};
  rep.target = {f.target_name, f.target.size()};
  rep.preset = o.preset;
  rep.search = in_loop ? o.search : std::string(registration::to_string(config.search.backend));
  rep.injection = registration::injection_of(config);
  rep.result = r;
  rep.work_spent = work_spent;
  rep.max_work = o.max_work;
  if (in_loop)
    rep.accelerator =
        registration::Report::Accelerator{ordered_json::parse(sampling_setting(accel_cfg.sim.sampling).dump()),
                                          ordered_json::parse(config_to_json(accel_cfg).dump()), accel_jobs};
  if (f.truth) rep.truth = registration::Report::Truth{f.truth_name, *f.truth, f.truth_warning};
  rep.config = registration::to_json(config);
  return rep;
}
}  // namespace

int run_register_command(const CLI::App& app, const RegisterOptions& o) {
  if (o.list_stages) {
    std::cout << registration::stage_list_json().dump(2) << '\n';
    return 0;
  }
  if (o.compare) return run_register_compare(app, o);
  if (app.count("--repeat"))
    throw std::invalid_argument("--repeat goes with --compare (it times the CPU back-ends of the comparison)");
  const bool in_loop = registration::in_loop(o.search);
  const registration::PipelineConfig config = pipeline_config(o, in_loop);
  if (o.list_config && o.json) {
    std::cout << registration::key_reference_json(config).dump(2) << '\n';
    return 0;
  }
  if (app.count("--json") && !o.list_config) throw std::invalid_argument("--json goes with --list-config");
  if (o.list_config) {
    std::cout << registration::key_reference(config, o.preset);
    return 0;
  }
  const hw::AcceleratorConfig accel_cfg = check_register_flags(app, o, in_loop);
  if (o.check_flags) return 0;

  FolderSpec spec{"register", {}, nlohmann::json::object(), register_inputs(o), {"registration.json"}, false, {}};
  spec.named = {{"--record-trace", o.record_trace}};
  OutFolder folder(o.out, spec);

  // The model server starts while the process is small (accel_in_loop.hpp).
  std::shared_ptr<ModelInTheLoop> model;
  if (in_loop)
    model = std::make_shared<ModelInTheLoop>(accel_cfg, WorkLimits{}, default_sim_threads(),
                                             o.jobs > 0 ? o.jobs : default_sim_threads());
  const FramePair f = load_frame_pair(frame_spec(o));

  std::fprintf(stderr, "tigris register: %s (%zu points) -> %s (%zu points), preset %s, search %s%s\n",
               f.source_name.c_str(), f.source.size(), f.target_name.c_str(), f.target.size(), o.preset.c_str(),
               registration::to_string(config.search.backend),
               registration::injection_text(registration::injection_of(config)).c_str());
  ordered_json accel_jobs = ordered_json::array();
  std::string stage;  // the stage running
  if (model)
    model->on_job = [&](std::uint64_t n, const registration::AccelJob& job, const nlohmann::json& rep) {
      registration::print_job_line(stderr, n, job, rep, stage);
      accel_jobs.push_back(registration::job_row(n, job, rep, stage));
    };
  const registration::RegisterRun run =
      registration::run_registration(f.source, f.target, config, o.max_work, !o.record_trace.empty(), model, stage);
  if (run.mismatch) return 1;
  const registration::RegistrationResult& r = run.result;

  registration::Report report = make_report(o, config, in_loop, f, r, run.work_spent, accel_cfg, accel_jobs);
  folder.check_inputs();
  if (run.recorder) report.trace = registration::write_trace(o.record_trace, *run.recorder, report, o.command_line);
  const std::string path = o.out + "/registration.json";
  write_file(path, [&](std::ostream& out) {
    out << registration::to_json(report).dump(2, ' ', false, ordered_json::error_handler_t::replace) << '\n';
  });  // paths: any bytes
  registration::print_summary(stdout, report, registration::to_string(config.search.backend), path);
  if (r.status != "converged") {
    std::fprintf(stderr, "tigris register: warning: %s: %s (status %s in %s; exit 1)\n",
                 r.status == "degenerate" ? "no transform" : "the transform is not a registration", r.problem.c_str(),
                 r.status.c_str(), path.c_str());
    folder.finish(r.status);
    return 1;
  }
  folder.finish();
  return 0;
}

namespace {

const CommandRegistration kRegistration{options_command<RegisterOptions>(
    "register",
    "Run the registration pipeline (outlier removal, normals, key points, descriptors, "
    "KPCE, rejection, ICP) with its KD-tree searches on the golden model, FLANN or the accelerator "
    "model in the loop; --compare: the four side by side",
    30,
    [](CLI::App& app, RegisterOptions& o) {
      o.out = "tigris-out/register";
      add_register_options(app, o);
    },
    [](const CLI::App& app, RegisterOptions& o, const CommandLine& line) {
      o.command_line = line.text;
      o.argv = line.argv;
      return run_register_command(app, o);
    })};

}  // namespace
}  // namespace tigris
