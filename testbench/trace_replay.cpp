#include "trace_replay.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <set>
#include <sstream>

#include "accel_job.hpp"
#include "config.hpp"
#include "core/children.hpp"
#include "core/input_file.hpp"
#include "core/json_file.hpp"
#include "core/out_folder.hpp"
#include "core/timer.hpp"
#include "report.hpp"
#include "sampling.hpp"
#include "sw_ref/accuracy.hpp"

namespace tigris {
namespace {

using nlohmann::json;

SearchParams params_of(const trace::Job& j) {
  SearchParams p;
  p.mode = j.mode == "nn" ? Mode::NN : j.mode == "knn" ? Mode::KNN : Mode::Radius;
  p.k = j.mode == "nn" ? 1 : j.k;
  p.radius = j.radius;
  p.max_nn = j.max_nn;
  p.approximate = j.approximate;
  p.approx_thd = j.approx_thd;
  p.leader_capacity = j.leader_capacity;
  p.leader_width = j.leader_width;
  p.leader_scope = parse_leader_scope(j.leader_scope);
  p.leader_in_flight = parse_leader_in_flight(j.leader_in_flight);
  return p;
}

Results recorded_results(const trace::Trace& t, const trace::Job& j) {
  const trace::JobResults r = trace::results(t, j);
  Results out;
  std::vector<Neighbor> list;
  for (std::size_t q = 0; q + 1 < r.offset.size(); ++q) {
    list.clear();
    for (std::uint64_t i = r.offset[q]; i < r.offset[q + 1]; ++i) list.push_back({r.index[i], r.dist2[i]});
    out.append_query(list.data(), list.data() + list.size());
  }
  return out;
}

std::uint64_t differing_queries(const Results& a, const Results& b) {
  std::uint64_t n = 0;
  for (std::size_t q = 0; q < a.num_queries() && q < b.num_queries(); ++q) {
    const bool same = a.count(q) == b.count(q) &&
                      std::equal(a.begin(q), a.end(q), b.begin(q), [](const Neighbor& x, const Neighbor& y) {
                        return x.index == y.index && std::memcmp(&x.dist2, &y.dist2, 4) == 0;
                      });
    n += same ? 0 : 1;
  }
  return n;
}

// One job in this (child) process: returns its report; exit code 0 match, 1 mismatch, 2 error.
json replay_job(const trace::Trace& t, const trace::Job& j, const ReplayedJob& plan, hw::AcceleratorConfig cfg,
                bool height_chosen, const WorkLimits& limits, int sim_threads, int& code) {
  const PointCloud& cloud = t.cloud(j.tree).points;
  const PointCloud& queries = t.cloud(j.queries).points;
  json r = {
      {"job", plan.index},
      {"stage", j.stage},
      {"iteration", j.iteration},
      {"mode", j.mode},
      {"k", j.k},
      {"radius", j.radius},
      {"max_nn", j.max_nn},
      {"approximate", j.approximate},
      {"queries", queries.size()},
      {"points", cloud.size()},
      {"cpu", {{"backend", j.backend}, {"search_seconds", j.search_seconds}, {"build_seconds", j.build_seconds}}}};
  ModelJob mj;
  mj.points = &cloud;
  mj.queries = &queries;
  mj.params = params_of(j);
  mj.top_height = height_chosen ? cfg.tree.top_height : j.top_height;
  mj.send_tree = plan.send_tree;
  ModelJobRun run = run_model_job(mj, cfg, limits, sim_threads);
  r.update(run.report);
  if (run.report["verdict"] == "deadlock") {
    code = 1;
    return r;
  }
  const Results recorded = recorded_results(t, j);
  const std::uint64_t differ = differing_queries(recorded, run.results);
  json vs_recorded = {{"queries_differing", differ}};
  if (differ > 0) vs_recorded["accuracy"] = accuracy_json(measure_accuracy(mj.params.mode, recorded, run.results));
  r["vs_recorded"] = vs_recorded;
  code = run.match ? 0 : 1;
  return r;
}

std::string job_path(const std::string& out, std::size_t i) {
  char b[32];
  std::snprintf(b, sizeof b, "/jobs/job_%05zu.json", i);
  return out + b;
}

// Adds `j`'s figures into the sums `s`.
void accumulate(json& s, const json& j) {
  if (s.is_null()) s = json::object();
  const auto add = [&](const char* key, double v) { s[key] = s.value(key, 0.0) + v; };
  add("jobs", 1);
  add("queries", j.at("queries").get<double>());
  add("cycles", j.value("cycles", 0.0));
  add("modeled_search_seconds", j.contains("modeled_seconds") ? j["modeled_seconds"]["search"].get<double>() : 0.0);
  add("modeled_host_seconds", j.contains("modeled_seconds") ? j["modeled_seconds"]["host"].get<double>() : 0.0);
  add("energy_pj", j.value("energy_pj", 0.0));
  add("cpu_search_seconds", j["cpu"]["search_seconds"].get<double>());
  add("cpu_build_seconds", j["cpu"]["build_seconds"].get<double>());
  add("queries_differing_from_recorded",
      j.contains("vs_recorded") ? j["vs_recorded"]["queries_differing"].get<double>() : 0.0);
}

ReplayResult collect_jobs(const trace::Trace& t, const TraceReplay& o, const std::vector<ReplayedJob>& plan,
                          const std::vector<int>& codes) {
  ReplayResult c;
  std::string first_error;
  for (std::size_t k = 0; k < plan.size(); ++k) {
    json r;
    try {
      const std::string path = job_path(o.out, plan[k].index);
      r = parse_json_text(read_input(path, "a job's report", kMaxSettingsBytes), path);
    } catch (const std::exception&) {
      r = {{"job", plan[k].index},
           {"error", "the job's process ended without a report (exit code " + std::to_string(codes[k]) + ")"}};
    }
    if (r.contains("error") && first_error.empty())
      first_error = "job " + std::to_string(plan[k].index) + " (" + t.jobs[plan[k].index].stage +
                    "): " + r["error"].get<std::string>();
    if (r.value("verdict", "") != "match") c.all_match = false;
    if (!r.contains("error")) {
      accumulate(c.per_stage[r["stage"].get<std::string>()], r);
      accumulate(c.total, r);
    }
    c.jobs.push_back(std::move(r));
  }
  if (!first_error.empty()) throw std::invalid_argument(o.trace + ": " + first_error);
  return c;
}

// The summary on stdout: a row per replayed stage (in the pipeline's order) and the total, and
// the registration end to end with the accelerator.
void print_table(const trace::Trace& t, const TraceReplay& o, std::size_t replayed, const ReplayResult& c,
                 const std::string& stats_path) {
  const json& end_to_end = c.end_to_end;
  const json& per_stage = c.per_stage;
  const json& total = c.total;
  const double e2e_cpu = end_to_end["cpu_seconds"].get<double>(),
               cpu_kd = end_to_end["cpu_kdtree_search_seconds"].get<double>(),
               e2e_accel = end_to_end["accelerated_seconds"].get<double>();
  std::printf("tigris run --trace %s: %zu of %zu jobs replayed: %s\n", o.trace.c_str(), replayed, t.jobs.size(),
              c.all_match ? "MATCH (every query of every job bit-exact)" : "MISMATCH");
  std::printf("  %-16s %5s %9s %12s %10s %10s %10s %10s %8s\n", "stage", "jobs", "queries", "cycles", "cpu-kd s",
              "accel s", "host s", "energy uJ", "kd x");
  const auto row = [](const std::string& name, const json& s) {
    std::printf("  %-16s %5.0f %9.0f %12.0f %10.4f %10.4f %10.4f %10.1f %8.1f\n", name.c_str(), s["jobs"].get<double>(),
                s["queries"].get<double>(), s["cycles"].get<double>(), s["cpu_search_seconds"].get<double>(),
                s["modeled_search_seconds"].get<double>(), s["modeled_host_seconds"].get<double>(),
                s["energy_pj"].get<double>() * 1e-6,
                s["cpu_search_seconds"].get<double>() / std::max(1e-12, s["modeled_search_seconds"].get<double>() +
                                                                            s["modeled_host_seconds"].get<double>()));
  };
  for (const trace::Stage& st : t.stages)  // in the pipeline's order
    if (per_stage.contains(st.name)) row(st.name, per_stage[st.name]);
  if (!total.empty()) row("total", total);
  std::printf(
      "  end to end: CPU %.3f s (KD-tree search %.3f s on %s) -> %.3f s with the accelerator: %.2fx, %.1f%% less "
      "(tree builds stay on the CPU)\n",
      e2e_cpu, cpu_kd, end_to_end["cpu_backend"].get<std::string>().c_str(), e2e_accel,
      end_to_end["speedup"].get<double>(), end_to_end["reduction_percent"].get<double>());
  if (total.value("queries_differing_from_recorded", 0.0) > 0)
    std::printf("  %.0f queries differ from the recorded results (see jobs[].vs_recorded)\n",
                total["queries_differing_from_recorded"].get<double>());
  std::printf("  stats   %s (per job: %s/jobs/)\n", stats_path.c_str(), o.out.c_str());
}

// Each job in a child process (SystemC elaborates once per process), o.jobs at a time; every job
// writes its report into OUT/jobs/. Returns the jobs' exit codes.
std::vector<int> replay_jobs(const trace::Trace& t, const TraceReplay& o, const std::vector<ReplayedJob>& plan) {
  const int parallel = std::max(1, o.jobs);
  const int sim_threads = parallel > 1 ? 1 : (o.sim_threads ? o.sim_threads : default_sim_threads());
  std::fflush(nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t done = 0;
  const auto replay_one = [&](std::size_t k) -> int {
    int code = 2;
    json r;
    const trace::Job& j = t.jobs[plan[k].index];
    try {
      r = replay_job(t, j, plan[k], o.cfg, o.height_chosen, o.limits, sim_threads, code);
    } catch (const std::exception& e) {
      r = {{"job", plan[k].index}, {"stage", j.stage}, {"error", e.what()}};
      code = 2;
    }
    try {
      write_file(job_path(o.out, plan[k].index),
                 [&](std::ostream& f) { f << r.dump(1, ' ', false, json::error_handler_t::replace) << '\n'; });
    } catch (const std::exception& e) {
      std::fprintf(stderr, "tigris run: %s\n", e.what());
      code = 2;
    }
    return code;
  };
  return run_pool(
      plan.size(), parallel, [&](std::size_t k) { return fork_child([&]() -> int { return replay_one(k); }); },
      [&](std::size_t k, int code) {
        const trace::Job& j = t.jobs[plan[k].index];
        std::fprintf(stderr, "tigris run --trace: job %zu/%zu (#%zu, %s%s, %s, %zu queries): %s (%.0f s)\n", ++done,
                     plan.size(), plan[k].index, j.stage.c_str(),
                     j.iteration >= 0 ? (" it " + std::to_string(j.iteration)).c_str() : "", j.mode.c_str(),
                     t.cloud(j.queries).points.size(),
                     code == 0   ? "match"
                     : code == 1 ? "MISMATCH"
                     : code == 2 ? "error"
                                 : "crashed",
                     seconds_since(t0));
        return true;
      });
}

// End to end: the recorded registration with its replayed stages' KD-tree searches replaced by
// the modeled search and host transfers; tree builds stay on the CPU. Adds each stage's speed-up.
json end_to_end_json(const trace::Trace& t, json& per_stage) {
  double cpu_kd = 0.0, modeled = 0.0;
  for (auto& [name, s] : per_stage.items()) {
    cpu_kd += s["cpu_search_seconds"].get<double>();
    modeled += s["modeled_search_seconds"].get<double>() + s["modeled_host_seconds"].get<double>();
    s["kdtree_speedup"] =
        s["cpu_search_seconds"].get<double>() /
        std::max(1e-12, s["modeled_search_seconds"].get<double>() + s["modeled_host_seconds"].get<double>());
  }
  const double e2e_cpu = t.total_seconds, e2e_accel = t.total_seconds - cpu_kd + modeled;
  return {
      {"cpu_seconds", e2e_cpu},
      {"cpu_kdtree_search_seconds", cpu_kd},
      {"accelerator_kdtree_seconds", modeled},
      {"accelerated_seconds", e2e_accel},
      {"speedup", e2e_cpu / std::max(1e-12, e2e_accel)},
      {"reduction_percent", 100.0 * (1.0 - e2e_accel / std::max(1e-12, e2e_cpu))},
      {"kdtree_speedup", cpu_kd / std::max(1e-12, modeled)},
      {"tree_builds", "on the CPU, as recorded (not modeled on the accelerator)"},
      {"cpu_backend", t.meta.contains("search") && t.meta["search"].is_string() ? t.meta["search"].get<std::string>()
                      : t.jobs.empty()                                          ? std::string()
                                                                                : t.jobs.front().backend}};
}

// The first job that did not match, on stderr.
void report_first_mismatch(const json& jobs) {
  for (const json& r : jobs)
    if (r.value("verdict", "") != "match") {
      std::fprintf(stderr, "tigris run --trace: job %s (%s) %s; first:\n", r["job"].dump().c_str(),
                   r["stage"].get<std::string>().c_str(), r.value("verdict", "").c_str());
      if (r.contains("mismatches"))
        for (const auto& m : r["mismatches"]["first"]) std::fprintf(stderr, "  %s\n", m.get<std::string>().c_str());
      return;
    }
}

}  // namespace

// The jobs to replay: those of --trace-stages (default: all), in the trace's order.
std::vector<ReplayedJob> plan_replay(const trace::Trace& t, const TraceReplay& o) {
  std::set<std::string> stages;
  for (const trace::Job& j : t.jobs) stages.insert(j.stage);
  std::set<std::string> wanted;
  if (!o.trace_stages.empty()) {
    std::stringstream list(o.trace_stages);
    std::string name;
    while (std::getline(list, name, ',')) {
      if (!stages.count(name)) {
        std::string have;
        for (const auto& s : stages) have += (have.empty() ? "" : ", ") + s;
        throw std::invalid_argument("--trace-stages: '" + name + "' is no stage with searches in " + o.trace +
                                    " (it has: " + have + ")");
      }
      wanted.insert(name);
    }
  }
  std::vector<ReplayedJob> plan;
  int last_tree = -1;
  for (std::size_t i = 0; i < t.jobs.size(); ++i) {
    if (!wanted.empty() && !wanted.count(t.jobs[i].stage)) continue;
    // The host sends a tree image when the job searches another tree than the job before it.
    plan.push_back({i, t.jobs[i].tree_serial != last_tree});
    last_tree = t.jobs[i].tree_serial;
  }
  return plan;
}

ReplayResult replay_trace(const trace::Trace& t, const TraceReplay& o, const std::vector<ReplayedJob>& plan) {
  const std::vector<int> codes = replay_jobs(t, o, plan);
  ReplayResult c = collect_jobs(t, o, plan, codes);
  c.end_to_end = end_to_end_json(t, c.per_stage);
  for (const json& j : c.jobs) c.sampled += j.contains("sampling") && j["sampling"].value("sampled", false);
  return c;
}

json replay_stats(const trace::Trace& t, const TraceReplay& o, std::size_t replayed, const ReplayResult& c) {
  json stats;
  stats["trace"] = {{"path", o.trace},
                    {"jobs", t.jobs.size()},
                    {"replayed", replayed},
                    {"stages", o.trace_stages.empty() ? "all" : o.trace_stages},
                    {"recorded", t.meta}};
  stats["verdict"] = c.all_match ? "match" : "mismatch";
  stats["config"] = config_to_json(o.cfg);
  stats["stages"] = c.per_stage;
  stats["total"] = c.total;
  stats["jobs"] = c.jobs;
  stats["sampled_jobs"] = c.sampled;  // their cycles and energy estimated (docs/sampling.md)
  stats["end_to_end"] = c.end_to_end;
  return stats;
}

void print_replay(const trace::Trace& t, const TraceReplay& o, std::size_t replayed, const ReplayResult& c,
                  const std::string& stats_path) {
  print_table(t, o, replayed, c, stats_path);
  if (o.cfg.sim.sampling != 0)
    std::printf("  sampled %zu of %zu jobs (sim.sampling %s): their cycles, energy and the totals are estimates\n",
                c.sampled, replayed, sampling_setting(o.cfg.sim.sampling).dump().c_str());
  if (!c.all_match) report_first_mismatch(c.jobs);
}

}  // namespace tigris
