#include "register_command.hpp"
#include "command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <stdexcept>

#include <pcl/console/print.h>
#include <nlohmann/json.hpp>

#include "core/arg_checks.hpp"
#include "core/flag_values.hpp"
#include "options.hpp"
#include "registration/pipeline.hpp"
#include "registration/report.hpp"
#include "testbench/accel_in_loop.hpp"
#include "testbench/config.hpp"
#include "testbench/presets.hpp"
#include "testbench/report.hpp"
#include "testbench/run_inputs.hpp"
#include "testbench/sampling.hpp"
#include "testbench/simulation.hpp"
#include "traces/workload_trace.hpp"
#include "workloads/io/cloud_io.hpp"
#include "workloads/pose.hpp"
#include "workloads/synthetic.hpp"

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
      ->check(CLI::IsMember({"flann", "exact", "approx", "accel", "accel-approx"}));
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
  registration::PipelineConfig config = registration::preset(o.preset);
  if (!o.config.empty()) registration::apply_file(config, o.config);
  for (const std::string& s : o.sets) registration::apply_set(config, s);
  // accel / accel-approx: the golden back-end's searches (exact / approx) on the model.
  if (!o.search.empty())
    config.search.backend = registration::parse_backend(o.search == "accel"          ? "exact"
                                                        : o.search == "accel-approx" ? "approx"
                                                                                     : o.search);
  if (!in_loop && (!o.accel_config.empty() || !o.accel_sets.empty()))
    throw std::invalid_argument(std::string(o.accel_config.empty() ? "--accel-set" : "--accel-config") +
                                " configures the accelerator in the loop: it needs --search accel or accel-approx");
  if (in_loop && !o.record_trace.empty())
    throw std::invalid_argument(
        "--record-trace records the CPU's searches: use --search flann, exact or approx "
        "(then tigris run --trace replays them on the accelerator)");
  if (!o.height.empty()) {
    const int h = parse_height(o.height);
    config.search.top_height = h < 0 ? 30 : h;  // 'full': the plug-in clamps to each cloud's
  }
  if (!o.approx_thd.empty()) {
    if (!o.search.empty() && o.search != "approx" && o.search != "accel-approx")
      throw std::invalid_argument("--approx-thd needs --search approx or accel-approx (got --search " + o.search + ")");
    const double t = parse_number("--approx-thd", o.approx_thd);
    config.search.backend = registration::Backend::Approx;
    // Through the keys, so the flag has the key's range and registration.json reads back.
    registration::apply_set(config, "search.nn_thd=" + o.approx_thd, "--approx-thd");
    config.search.radius_thd = std::min(1.0, 0.4 * t / 1.2);
  }
  const bool injecting = !o.inject_kth.empty() || !o.inject_shell.empty();
  if (!o.inject_kth.empty()) config.inject.rpce_kth = parse_kth(o.inject_kth);
  if (!o.inject_shell.empty()) {
    parse_shell(o.inject_shell, config.normals.radius);  // the form R1,R2 and R1 < r < R2
    const std::size_t at = o.inject_shell.find(',');
    registration::apply_set(config, "inject.normals_shell_inner=" + o.inject_shell.substr(0, at), "--inject-shell");
    registration::apply_set(config, "inject.normals_shell_outer=" + o.inject_shell.substr(at + 1), "--inject-shell");
  }
  if (injecting && config.search.backend == registration::Backend::Approx)
    throw std::invalid_argument(std::string(!o.inject_kth.empty() ? "--inject-kth" : "--inject-shell") +
                                " needs --search exact, flann or accel (error injection measures exact search; "
                                "got search " +
                                (in_loop ? o.search : std::string("approx")) + ")");
  registration::validate(config, "tigris register");
  return config;
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

// The two frames and the ground truth, when there is one.
struct FramePair {
  PointCloud source, target;
  std::string source_name, target_name;
  std::optional<Pose> truth;
  std::string truth_name, truth_warning;
};

FramePair load_frames(const RegisterOptions& o) {
  FramePair f;
  if (o.source.empty()) {
    SyntheticConfig sc;
    sc.seed = o.seed;
    const SyntheticPair pair = make_synthetic_pair(sc);
    f.source = pair.frame1;
    f.target = pair.frame0;
    const std::string tag = " (seed " + std::to_string(o.seed) + ")";
    f.source_name = "synthetic:frame1" + tag;
    f.target_name = "synthetic:frame0" + tag;
    Pose t;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) t(r, c) = pair.frame1_to_frame0[static_cast<std::size_t>(4 * r + c)];
    f.truth = t;
    f.truth_name = "synthetic pair's known pose";
  } else {
    f.source = load_cloud(o.source);
    f.target = load_cloud(o.target);
    f.source_name = o.source;
    f.target_name = o.target;
  }
  if (!o.ground_truth.empty()) {
    f.truth = read_pose_file(o.ground_truth);
    f.truth_name = o.ground_truth;
  } else if (!o.kitti_poses.empty()) {
    const auto [s, t] = parse_frame_pair(o.kitti_frames);
    f.truth = kitti_relative_velo_pose(o.kitti_poses, s, t);
    f.truth_name = o.kitti_poses + " frames " + o.kitti_frames + " (camera -> Velodyne axes)";
    // Both frames within a run of equal ground-truth steps from frame 0 (KITTI 00's first ~15).
    const std::size_t steps = equal_steps(read_kitti_poses(o.kitti_poses));
    if (steps >= kEqualStepsWarn && static_cast<std::size_t>(std::max(s, t)) <= steps)
      f.truth_warning = equal_steps_warning(steps);
  }
  return f;
}

// The injected error, as the summary lines say it ("" when none).
std::string injection_text(const registration::PipelineConfig& config) {
  std::string injection;
  if (config.inject.rpce_kth > 1)
    injection += ", RPCE returns the K-th nearest (K = " + std::to_string(config.inject.rpce_kth) + ")";
  if (config.inject.normals_shell_outer > 0) {
    char buf[96];
    std::snprintf(buf, sizeof buf, ", normals search the shell %g..%g m (r %g)", config.inject.normals_shell_inner,
                  config.inject.normals_shell_outer, config.normals.radius);
    injection += buf;
  }
  return injection;
}

// A line per accelerator job on stderr, and the job's row of registration.json.
ordered_json accel_job_row(std::uint64_t n, const registration::AccelJob& job, const nlohmann::json& rep,
                           const std::string& stage) {
  const double modeled = rep.contains("modeled_seconds") ? rep["modeled_seconds"]["total"].get<double>() : 0.0;
  const nlohmann::json sampling = rep.value("sampling", nlohmann::json::object());
  const bool sampled = sampling.value("sampled", false);
  std::fprintf(
      stderr,
      "tigris register: %s: accelerator job %llu (%s, %zu queries on %zu points): %s, %s%.3g ms modeled, %.1f s "
      "simulated%s\n",
      stage.c_str(), static_cast<unsigned long long>(n), to_string(job.params.mode), job.queries->size(),
      job.points->size(), rep.value("verdict", "?").c_str(), sampled ? "~" : "", 1e3 * modeled,
      rep.value("wall_seconds", 0.0),
      sampled ? (" (sampled: " + std::to_string(sampling.value("simulated", 0)) + " queries simulated)").c_str() : "");
  ordered_json j;
  j["job"] = n;
  j["stage"] = stage;
  j["mode"] = to_string(job.params.mode);
  j["k"] = job.params.effective_k();
  j["radius"] = job.params.radius;
  j["approximate"] = job.params.approximate;
  j["queries"] = job.queries->size();
  j["points"] = job.points->size();
  j["verdict"] = rep.value("verdict", "");
  j["cycles"] = rep.value("cycles", 0);
  j["cycles_ci95"] = rep.value("cycles_ci95", nlohmann::json());  // [cycles, cycles] unless sampled
  j["sampled"] = sampled;
  j["simulated_queries"] = sampling.value("simulated", 0);
  j["modeled_seconds"] = rep.value("modeled_seconds", nlohmann::json());
  j["energy_pj"] = rep.value("energy_pj", 0.0);
  return j;
}

// Writes the workload trace of the registration (--record-trace); returns registration.json's "trace".
ordered_json write_trace(const RegisterOptions& o, registration::TraceRecorder& recorder, const ordered_json& doc,
                         const registration::RegistrationResult& r) {
  trace::Trace t = recorder.finish();
  t.meta = nlohmann::json::parse(
      doc.dump(-1, ' ', false,
               ordered_json::error_handler_t::replace));  // the registration's report, without its stages' details
  t.meta.erase("stages");
  t.meta["command_line"] = o.command_line;
  t.total_seconds = r.total_seconds;
  for (const auto& s : r.stages) {  // the time spent recording is not the registration's
    const double overhead = recorder.overhead(s.name);
    t.stages.push_back({s.name, s.seconds - overhead, s.kdtree.search_seconds, s.kdtree.build_seconds});
    t.total_seconds -= overhead;
  }
  t.meta["seconds"] = t.total_seconds;  // registration.json's, which includes the recording
  t.meta["seconds_recording"] = r.total_seconds - t.total_seconds;
  const std::vector<std::uint8_t> bytes = trace::encode(t);
  write_file(o.record_trace, [&](std::ostream& f) {
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  });
  std::fprintf(stderr, "tigris register: trace %s: %zu jobs, %zu clouds\n", o.record_trace.c_str(), t.jobs.size(),
               t.clouds.size());
  return {{"path", o.record_trace}, {"jobs", t.jobs.size()}, {"clouds", t.clouds.size()}};
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
  rep.injection = {config.inject.rpce_kth, config.inject.normals_shell_inner, config.inject.normals_shell_outer,
                   config.normals.radius};
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
// The accelerator's figures per stage and in all, and whether jobs were sampled.
void print_loop(const registration::Report& rep) {
  const registration::RegistrationResult& r = rep.result;
  std::printf("  on the accelerator (modeled; every job bit-exact against the golden model):\n");
  std::printf("  %-16s %5s %9s %9s %12s %10s %10s %10s\n", "stage", "jobs", "queries", "fallback", "cycles", "kd s",
              "stage s", "energy uJ");
  for (const auto& s : r.stages) {
    if (s.search.empty()) continue;
    const auto& a = s.kdtree.accel;
    std::printf("  %-16s %5llu %9llu %9llu %12llu %10.5f %10.4f %10.2f\n", s.name.c_str(),
                static_cast<unsigned long long>(a.jobs), static_cast<unsigned long long>(a.queries),
                static_cast<unsigned long long>(a.fallback_searches), static_cast<unsigned long long>(a.cycles),
                registration::modeled_kdtree_seconds(s.kdtree), registration::modeled_stage_seconds(s),
                a.energy_pj * 1e-6);
  }
  const registration::LoopFigures l = registration::loop_figures(r);
  std::printf("  end to end %.4f s modeled (KD-tree %.5f s, %.1f uJ); %.1f s of wall time, simulation included\n",
              l.modeled_e2e, l.modeled_kd, l.energy_pj * 1e-6, r.total_seconds);
}

// How the accelerator's jobs were simulated (after the summary: estimates must be read as such).
void print_sampling(const registration::Report& rep) {
  const std::uint64_t sampled = rep.sampled_jobs(), jobs = registration::loop_figures(rep.result).jobs;
  const ordered_json& a = rep.accelerator->sampling;
  const std::string setting = a.is_string() ? a.get<std::string>() : a.dump();
  if (sampled > 0)
    std::printf(
        "  sampled %llu of %llu accelerator jobs (sim.sampling %s): their cycles and energy are estimates; "
        "--accel-set sim.sampling=off simulates every query\n",
        static_cast<unsigned long long>(sampled), static_cast<unsigned long long>(jobs), setting.c_str());
  else
    std::printf("  every query of the %llu accelerator jobs simulated (sim.sampling %s%s)\n",
                static_cast<unsigned long long>(jobs), setting.c_str(),
                setting == "off" ? "" : ": no job long enough to sample");
}

// The summary on stdout: stages, the accelerator's figures, the transform and its error.
void print_registration(const registration::PipelineConfig& config, const registration::Report& rep,
                        const std::string& injection, const std::string& path) {
  const registration::RegistrationResult& r = rep.result;
  std::printf("tigris register: preset %s, search %s, %llu -> %llu points%s\n", rep.preset.c_str(),
              registration::to_string(config.search.backend), static_cast<unsigned long long>(rep.source.points),
              static_cast<unsigned long long>(rep.target.points), injection.c_str());
  std::printf("  %-16s %9s %10s %11s\n", "stage", "seconds", "kd-queries", "kd-seconds");
  for (const auto& s : r.stages)
    std::printf("  %-16s %9.3f %10llu %11.3f\n", s.name.c_str(), s.seconds,
                static_cast<unsigned long long>(s.kdtree.searches), s.kdtree.search_seconds + s.kdtree.build_seconds);
  if (rep.in_loop())
    print_loop(rep);
  else
    std::printf("  total %.3f s, KD-tree share %.1f%%\n", r.total_seconds,
                100.0 * (r.total_seconds > 0 ? rep.kdtree_seconds() / r.total_seconds : 0.0));
  if (r.status != "degenerate") {
    std::printf("  transform (target <- source)%s:\n", r.status == "converged" ? "" : ", NOT CONVERGED");
    for (int i = 0; i < 3; ++i)
      std::printf("    %10.6f %10.6f %10.6f %10.4f\n", r.transform(i, 0), r.transform(i, 1), r.transform(i, 2),
                  r.transform(i, 3));
  }
  const std::optional<PoseError> err = rep.error();
  if (err && std::isfinite(err->translation_per_m))
    std::printf("  error vs ground truth: translation %.4f m, rotation %.4f deg (%.4f m/m, %.4f deg/m over %.3f m)\n",
                err->translation_m, err->rotation_deg, err->translation_per_m, err->rotation_deg_per_m,
                err->travelled_m);
  else if (err)
    std::printf(
        "  error vs ground truth: translation %.4f m, rotation %.4f deg (per metre: n/a, the ground truth "
        "does not move)\n",
        err->translation_m, err->rotation_deg);
  if (err && !rep.truth->warning.empty()) std::printf("  warning: %s\n", rep.truth->warning.c_str());
  std::printf("  wrote %s\n", path.c_str());
  if (rep.in_loop()) print_sampling(rep);
}

// The registration, its progress on stderr (stage by stage, the work bound), each accelerator
// job's row into `accel_jobs`.
struct PipelineRun {
  registration::RegistrationResult result;
  double work_spent = 0;                                  // distances and neighbours, against --max-work
  std::shared_ptr<registration::TraceRecorder> recorder;  // --record-trace
  bool mismatch = false;  // a job's results differed from the golden model's (reported; exit 1)
};

PipelineRun run_pipeline(const RegisterOptions& o, const registration::PipelineConfig& config, const FramePair& f,
                         std::shared_ptr<ModelInTheLoop> model, ordered_json& accel_jobs) {
  // PCL's own messages (e.g. SHOT's "local reference frame is not valid" per dropped key point)
  // would flood stderr: the counts are in registration.json instead.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  auto budget = std::make_shared<registration::WorkBudget>();
  budget->limit = o.max_work;
  std::string stage_now;
  budget->progress = [&](const registration::WorkBudget& b) {
    std::fprintf(stderr, "tigris register: %s: %llu searches so far, %.3g distances and neighbours (--max-work %.3g)\n",
                 stage_now.c_str(), static_cast<unsigned long long>(b.searches), b.spent, b.limit);
  };
  registration::PipelineHooks hooks;
  hooks.on_stage = [&](const std::string& stage) {
    stage_now = stage;
    std::fprintf(stderr, "tigris register: %s...\n", stage.c_str());
  };
  hooks.budget = budget;
  PipelineRun run;
  if (!o.record_trace.empty()) run.recorder = hooks.recorder = std::make_shared<registration::TraceRecorder>();
  if (model) {
    model->on_job = [&](std::uint64_t n, const registration::AccelJob& job, const nlohmann::json& rep) {
      accel_jobs.push_back(accel_job_row(n, job, rep, stage_now));
    };
    hooks.accelerator = std::move(model);
  }
  try {
    run.result = registration::register_clouds(f.source, f.target, config, hooks);
  } catch (const registration::AcceleratorFailure& e) {
    std::fprintf(stderr, "tigris register: MISMATCH in stage %s: %s\n", stage_now.c_str(), e.what());
    run.mismatch = true;
  } catch (const registration::WorkLimitExceeded& e) {
    throw std::invalid_argument(std::string(e.what()) + " in stage " + stage_now +
                                "; raise --max-work (0: no limit) if the registration is meant to be that large, or "
                                "check the injection, radii and k of the configuration");
  }
  run.work_spent = budget->spent;
  return run;
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
  const bool in_loop = o.search == "accel" || o.search == "accel-approx";
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
  const FramePair f = load_frames(o);

  const std::string injection = injection_text(config);
  std::fprintf(stderr, "tigris register: %s (%zu points) -> %s (%zu points), preset %s, search %s%s\n",
               f.source_name.c_str(), f.source.size(), f.target_name.c_str(), f.target.size(), o.preset.c_str(),
               registration::to_string(config.search.backend), injection.c_str());
  ordered_json accel_jobs = ordered_json::array();
  PipelineRun run = run_pipeline(o, config, f, std::move(model), accel_jobs);
  if (run.mismatch) return 1;
  const registration::RegistrationResult& r = run.result;

  registration::Report report = make_report(o, config, in_loop, f, r, run.work_spent, accel_cfg, accel_jobs);
  folder.check_inputs();
  if (run.recorder) report.trace = write_trace(o, *run.recorder, registration::to_json(report), r);
  const std::string path = o.out + "/registration.json";
  write_file(path, [&](std::ostream& out) {
    out << registration::to_json(report).dump(2, ' ', false, ordered_json::error_handler_t::replace) << '\n';
  });  // paths: any bytes
  print_registration(config, report, injection, path);
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
