#include "trace_replay.hpp"

#include <chrono>
#include <cstdio>

#include "core/out_folder.hpp"
#include "core/timer.hpp"
#include "testbench/config.hpp"
#include "testbench/run_inputs.hpp"
#include "testbench/trace_replay.hpp"

namespace tigris {

int run_trace_replay(const CLI::App& app, const RunOptions& o) {
  for (const char* flag : {"--cloud", "--queries", "--mode", "--k", "--radius", "--max-nn", "--approx-thd",
                           "--leader-width", "--dump-results", "--dump-schedule", "--vcd", "--timeline", "--seed"})
    if (app.count(flag))
      throw std::invalid_argument(std::string(flag) +
                                  " does not go with --trace: the trace's jobs say what is searched");
  TraceReplay r;
  r.trace = o.trace;
  r.trace_stages = o.trace_stages;
  r.out = o.search.out;
  r.cfg = accelerator_config(app, o);
  validate_config(r.cfg);
  r.height_chosen = app.count("--height") > 0 || r.cfg.tree.top_height != hw::AcceleratorConfig{}.tree.top_height;
  r.limits = o.search.limits;
  r.jobs = o.jobs;
  r.sim_threads = o.sim_threads;

  const trace::Trace t = trace::read_trace(o.trace);
  const std::vector<ReplayedJob> plan = plan_replay(t, r);
  const std::string stats_path = o.search.out + "/stats.json";
  nlohmann::json inputs = nlohmann::json::array({input_file("trace", o.trace)});
  if (!o.config_file.empty()) inputs.push_back(input_file("config", o.config_file));
  // A fresh start: an earlier replay's jobs/ never sits beside this one's stats.json.
  OutFolder folder(o.search.out, {"run", {}, nlohmann::json::object(), inputs, {"stats.json", "jobs/"}, false, {}});

  const auto t0 = std::chrono::steady_clock::now();
  const ReplayResult c = replay_trace(t, r, plan);
  nlohmann::json stats = replay_stats(t, r, plan.size(), c);
  stats["command"] = "run --trace";
  stats["command_line"] = o.search.command_line;
  stats["inputs"] = inputs;
  stats["wall_seconds"] = seconds_since(t0);
  folder.check_inputs();
  write_file(stats_path, [&](std::ostream& f) {
    f << stats.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
  });
  print_replay(t, r, plan.size(), c, stats_path);
  folder.finish(c.all_match ? "done" : "failed");
  return c.all_match ? 0 : 1;
}

}  // namespace tigris
