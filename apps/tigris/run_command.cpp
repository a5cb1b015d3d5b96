#include "run_command.hpp"
#include "command.hpp"

#include <cstdio>
#include <iostream>
#include <optional>

#include "core/arg_checks.hpp"
#include "core/out_folder.hpp"
#include "core/progress.hpp"
#include "testbench/accel_job.hpp"
#include "testbench/config.hpp"
#include "testbench/presets.hpp"
#include "testbench/run_inputs.hpp"
#include "testbench/run_record.hpp"
#include "testbench/simulation.hpp"
#include "testbench/stats_schema.hpp"
#include "testbench/timeline.hpp"
#include "trace_replay.hpp"
#include "traces/schedule_csv.hpp"
#include "workloads/workload.hpp"

namespace tigris {

void add_run_options(CLI::App& app, RunOptions& o) {
  add_search_options(app, o.search);
  input_flag(
      app.add_option("--config", o.config_file,
                     "Accelerator configuration: a preset's name (tigris presets lists them, e.g. paper, dram-2x) or a "
                     "JSON file nested by block (presets/paper.json writes out every key)"))
      ->transform(preset_or_file());
  app.add_option("--set", o.settings, "Override one configuration key, e.g. --set fe.recursion_units=32 (repeatable)");
  output_flag(app.add_option(
      "--vcd", o.vcd,
      "Write waveforms as VCD, and a GTKWave save file beside it (same name, .gtkw): machine-wide "
      "counts of RUs busy and stalled by cause, PEs busy, waiting for data and held by the write-back, "
      "BQB occupancy, write-back backlog; per unit its busy and stall flags, queue occupancies, query ids"));
  output_flag(
      app.add_option("--timeline", o.timeline,
                     "Write the run as a Chrome trace-event JSON (open in ui.perfetto.dev or "
                     "chrome://tracing): whole-machine counters over every query (RUs and PEs busy and stalled, BQB "
                     "occupancy, write-back backlog), and a track per RU, QDN port, SU and the write-back with a slice "
                     "per walk, hop, BQB wait and batch and flow arrows per query, for the sampled queries"));
  app.add_option("--timeline-queries", o.timeline_queries,
                 "About how many queries the timeline's slices show (every n-th query; 0: all); its "
                 "whole-machine counters cover every query either way")
      ->check(whole_range(0, 4294967295LL))
      ->capture_default_str();
  app.add_option("--sim-threads", o.sim_threads,
                 "Host threads for the simulation: 2 runs exact NN/kNN scans on a second thread, 1 "
                 "keeps everything on one (the figures are the same). Default: 2 on a machine with "
                 "two or more cores, else 1")
      ->check(CLI::Range(1, 2));
  input_flag(
      app.add_option("--trace", o.trace,
                     "Replay a registration's workload trace (tigris register --record-trace): every job through the "
                     "model as the host would run it, each query checked; per job, stage and total figures and the "
                     "end-to-end time with the accelerator"));
  app.add_option("--trace-stages", o.trace_stages,
                 "With --trace: replay only these stages, comma-separated (e.g. normals,icp; default: all)");
  app.add_option("--jobs", o.jobs,
                 "With --trace: jobs simulated at a time, each in a process of its own (the "
                 "figures do not depend on it)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  app.add_flag("--list-config", o.list_config,
               "Print every configuration key with its default, unit, allowed values and meaning as a Markdown "
               "table, and exit");
  app.add_flag("--json", o.json,
               "With --list-config: print the keys as JSON (type, unit, default, range or names, "
               "meaning), for tools");
  app.add_flag("--stats-schema", o.stats_schema,
               "Print the schema of stats.json as JSON (every field's path, unit and meaning; derived fields with "
               "their formula) and exit");
}

namespace {

constexpr const char* kEveryQuerySchedule = "--dump-schedule (the leaf visits of every query)";

// The files run's flags name (claimed with the output folder).
std::vector<NamedOutput> named_outputs(const RunOptions& o) {
  return {{"--vcd", o.vcd},
          {"--vcd (GTKWave save file)", o.vcd.empty() || is_stream_path(o.vcd) ? "" : gtkw_path(o.vcd), true},
          {"--timeline", o.timeline},
          {"--dump-results", o.search.dump_results},
          {"--dump-schedule", o.search.dump_schedule}};
}

}  // namespace

hw::AcceleratorConfig accelerator_config(const CLI::App& app, const RunOptions& o) {
  hw::AcceleratorConfig cfg;
  if (!o.config_file.empty()) apply_config_file(cfg, o.config_file);
  for (const std::string& s : o.settings) apply_setting(cfg, s);
  if (app.count("--height")) cfg.tree.top_height = parse_height(o.search.height);
  if (app.count("--split-axis")) cfg.tree.split_axis = parse_split_rule(o.search.split_axis);
  return cfg;
}

namespace {

// Configure: the flags, the configuration (file, --set, flags over them), the workload and its
// tree; refuses a job that does not fit the buffers or exceeds the work limits.
RunSetup configure_run(const CLI::App& app, const RunOptions& o) {
  std::vector<PathUse> outputs{{"--out (stats.json)", o.search.out + "/stats.json"}};
  for (const NamedOutput& n : named_outputs(o)) outputs.push_back({n.flag, n.path});
  check_distinct_paths({{"--cloud", o.search.cloud}, {"--queries", o.search.queries}, {"--config", o.config_file}},
                       outputs);
  RunSetup r;
  hw::AcceleratorConfig cfg = accelerator_config(app, o);
  r.params = search_params(app, o.search, cfg.leader.scope, cfg.leader.in_flight);
  // The Leader Buffer's capacity is hardware: --leader-capacity sets leader.capacity_per_leaf.
  if (app.count("--leader-capacity")) cfg.leader.capacity_per_leaf = o.search.leader_capacity;
  if (app.count("--leader-width")) cfg.leader.width = o.search.leader_width;  // so is the leaders' list width
  cfg.leader.scope = r.params.leader_scope;                                   // the flags over the configuration
  cfg.leader.in_flight = r.params.leader_in_flight;
  validate_config(cfg);
  r.params.leader_capacity = cfg.leader.capacity_per_leaf;
  r.params.leader_width = cfg.leader.width;
  r.params.leader_scope = cfg.leader.scope;
  r.params.leader_in_flight = cfg.leader.in_flight;

  r.w = load_workload(o.search.cloud, o.search.queries, o.search.seed);
  const Workload& w = r.w;
  note_k_above_cloud("tigris run", r.params, w.cloud.size(), w.cloud_name);
  r.inputs = search_inputs(o.search.cloud, o.search.queries, w.cloud_name, w.queries_name, o.config_file);
  // The default top height only: one from --height, --set or --config stays as asked.
  const bool height_chosen =
      app.count("--height") > 0 || cfg.tree.top_height != hw::AcceleratorConfig{}.tree.top_height;
  cfg.tree.top_height = default_height_for(cfg.tree.top_height, height_chosen, w.cloud.size(), w.cloud_name);
  r.p = prepare_job(w.cloud, w.queries, r.params, cfg, o.search.limits,
                    w.cloud_name + " (" + std::to_string(w.cloud.size()) + " points): ");
  // An output that needs every query is refused now, before the folder's earlier run is replaced.
  check_every_query(job_plan(r.p, r.params, w.queries.size()), !o.vcd.empty() || !o.timeline.empty(),
                    o.search.dump_schedule.empty() ? "" : kEveryQuerySchedule);
  return r;
}

// Simulate: the golden model's exact search in query order (what an exact run must reproduce;
// an approximate run is checked against the replay of its own schedule and measured against
// these exact results), then the accelerator, then the check. Nullopt after a deadlock, which
// it reports.
std::optional<JobOutcome> simulate_run(const RunSetup& r, const RunOptions& o, const OutFolder& folder,
                                       TimelineRecorder& timeline) {
  SimExtras extras;
  extras.vcd_path = o.vcd;
  if (!o.vcd.empty() && !is_stream_path(o.vcd) && folder.writes(gtkw_path(o.vcd))) extras.gtkw_path = gtkw_path(o.vcd);
  if (!o.vcd.empty())
    extras.provenance = provenance_lines(provenance_json(o.search.command_line, r.inputs, run_config_json(r)));
  if (o.sim_threads) extras.sim_threads = o.sim_threads;
  if (!o.search.dump_schedule.empty()) extras.every_query = kEveryQuerySchedule;
  const auto queries = static_cast<std::uint32_t>(r.w.queries.size());
  if (!o.timeline.empty()) {
    extras.observers.push_back(&timeline);
    const std::uint32_t shown = o.timeline_queries == 0 ? queries : o.timeline_queries;
    const std::uint32_t stride = TimelineRecorder::stride_for(queries, shown);
    const double sampled = static_cast<double>(queries) / stride;
    const double bytes = TimelineRecorder::estimated_bytes(sampled, r.p.estimate.leaf_visits_per_query);
    if (bytes > 100e6)
      std::fprintf(
          stderr,
          "tigris run: note: the timeline of %.0f queries (--timeline-queries %u) will be about %.0f MB of JSON "
          "(about 1 KB per leaf visit) and takes minutes to write and to open; --timeline-queries 2000 "
          "samples the slices (the whole-machine counters stay exact)\n",
          sampled, o.timeline_queries, bytes * 1e-6);
  }
  ProgressReporter progress("tigris run: queries finished");
  extras.progress = [&](std::uint32_t done, std::uint32_t total) { progress(done, total); };
  JobOutcome m = run_job(r.p, r.w.cloud, r.w.queries, r.params, extras);
  if (!m.sim.finished) {
    std::cerr << "tigris run: DEADLOCK: the simulation ran out of events with work left:\n" << m.sim.deadlock;
    return std::nullopt;
  }
  return m;
}

}  // namespace

int run_run_command(const CLI::App& app, const RunOptions& o) {
  if (o.list_config) {
    std::cout << (o.json ? config_reference_json().dump(2) + "\n" : config_reference());
    return 0;
  }
  if (o.stats_schema) {
    std::cout << stats_schema_json().dump(2) << '\n';
    return 0;
  }
  if (app.count("--json")) throw std::invalid_argument("--json goes with --list-config");
  if (!o.trace.empty()) return run_trace_replay(app, o);
  if (app.count("--trace-stages") || app.count("--jobs"))
    throw std::invalid_argument(std::string(app.count("--jobs") ? "--jobs" : "--trace-stages") + " goes with --trace");

  const RunSetup r = configure_run(app, o);
  FolderSpec spec{"run",
                  {},
                  nlohmann::json::object(),
                  search_inputs(o.search.cloud, o.search.queries, r.w.cloud_name, r.w.queries_name, o.config_file),
                  {"stats.json"},
                  false,
                  {}};
  spec.named = named_outputs(o);
  OutFolder folder(o.search.out, spec);
  const std::uint32_t shown =
      o.timeline_queries == 0 ? static_cast<std::uint32_t>(r.w.queries.size()) : o.timeline_queries;
  TimelineRecorder timeline(1000.0 / r.p.cfg.clock_mhz, shown);
  const std::optional<JobOutcome> m = simulate_run(r, o, folder, timeline);
  if (!m) {
    folder.finish("failed");
    return 1;
  }

  folder.check_inputs();
  if (!o.search.dump_schedule.empty())
    folder.write(o.search.dump_schedule, [&](std::ostream& f) { write_schedule_csv(f, m->sim.visits.schedule); });
  Accuracy accuracy;
  const nlohmann::json stats = run_stats(r, *m, o.search.command_line, accuracy);
  const std::string stats_path = o.search.out + "/stats.json";
  write_file(stats_path, [&](std::ostream& f) {
    f << stats.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
  });
  if (!o.timeline.empty())
    folder.write(o.timeline, [&](std::ostream& f) {
      nlohmann::json trace = timeline.trace();
      trace["otherData"]["run"] = provenance_json(o.search.command_line, r.inputs, stats["config"]);
      f << trace.dump() << '\n';
    });
  if (!o.search.dump_results.empty())
    folder.write(o.search.dump_results, [&](std::ostream& f) { write_results_csv(f, m->sim.results); });

  print_run_summary(r, *m, stats, accuracy, stats_path);
  if (!o.timeline.empty())
    std::printf("  timeline %s (slices: %s; counters: every query; open in ui.perfetto.dev)\n", o.timeline.c_str(),
                timeline.trace_note().c_str());
  if (!o.vcd.empty()) std::printf("  waves   %s (open: gtkwave %s)\n", o.vcd.c_str(), gtkw_path(o.vcd).c_str());
  if (!m->verdict.match) {
    std::fprintf(stderr, "tigris run: %llu queries with other results, %llu with other visit counts; first:\n",
                 static_cast<unsigned long long>(m->verdict.result_mismatches),
                 static_cast<unsigned long long>(m->verdict.visit_mismatches));
    for (const std::string& line : m->verdict.first) std::fprintf(stderr, "  %s\n", line.c_str());
    folder.finish("failed");
    return 1;
  }
  folder.finish();
  return 0;
}

namespace {

const CommandRegistration kRegistration{options_command<RunOptions>(
    "run",
    "Run the accelerator model; every query is checked against the golden model "
    "(exit 0 only when all match, 1 on a mismatch or deadlock)",
    20,
    [](CLI::App& app, RunOptions& o) {
      o.search.out = "tigris-out/run";
      add_run_options(app, o);
    },
    [](const CLI::App& app, RunOptions& o, const CommandLine& line) {
      o.search.command_line = line.text;
      return run_run_command(app, o);
    })};

}  // namespace
}  // namespace tigris
