#include "accel_job.hpp"

#include <chrono>
#include <exception>
#include <stdexcept>
#include <thread>

#include "config.hpp"
#include "report.hpp"
#include "scoreboard.hpp"
#include "simulation.hpp"
#include "tlm/tree_image.hpp"

namespace tigris {

double link_seconds(const hw::AcceleratorConfig& cfg, double bytes) {
  return cfg.host.link_latency_us * 1e-6 + bytes / (cfg.host.link_gb_per_s * 1e9);
}

namespace {
double since(std::chrono::steady_clock::time_point& t) {
  const auto now = std::chrono::steady_clock::now();
  const double s = std::chrono::duration<double>(now - t).count();
  t = now;
  return s;
}
}  // namespace

ModelJobRun run_model_job(const ModelJob& mj, hw::AcceleratorConfig cfg, const WorkLimits& limits, int sim_threads) {
  auto t_phase = std::chrono::steady_clock::now();
  nlohmann::json phases;
  const PointCloud& cloud = *mj.points;
  const PointCloud& queries = *mj.queries;
  const SearchParams& params = mj.params;
  cfg.tree.top_height = std::min(mj.top_height, full_height_for(cloud.size()));
  if (params.approximate) cfg.leader.capacity_per_leaf = params.leader_capacity, cfg.leader.scope = params.leader_scope,
                                cfg.leader.in_flight = params.leader_in_flight;
  validate_config(cfg);
  const KdTree tree = build_kdtree(cloud, cfg.tree.top_height, cfg.tree.split_axis);
  const tlm_if::TreeImage image = tlm_if::encode_tree_image(tree);
  const HostJob job = host_job(params);
  const std::string fit =
      hw::job_fit_error(cfg, image.bytes.size(), queries.size(), tree.top_height, job.mode, job.k,
                        job.approximate && job.first_leaf);
  if (!fit.empty()) throw std::invalid_argument("does not fit the accelerator: " + fit);
  check_work(estimate_work(tree, queries, params), limits, queries.size());
  phases["prepare"] = since(t_phase);

  SearchParams exact = params;
  exact.approximate = false;
  const auto t0 = std::chrono::steady_clock::now();
  const SearchOutput golden = search(tree, queries, exact);
  phases["golden"] = since(t_phase);
  SimSetup setup;
  setup.config = cfg;
  setup.image = &image;
  setup.queries = &queries;
  setup.num_points = static_cast<std::uint32_t>(cloud.size());
  setup.job = job;
  setup.sim_threads = sim_threads;
  SimOutcome sim;
  std::exception_ptr failure;
  std::thread([&] {  // SystemC on a thread of its own, as tigris run does (sanitizer stacks)
    try {
      sim = simulate({setup}).front();
    } catch (...) {
      failure = std::current_exception();
    }
  }).join();
  if (failure) std::rethrow_exception(failure);
  if (!sim.error.empty()) throw std::invalid_argument(sim.error);
  phases["simulate"] = since(t_phase);
  ModelJobRun run;
  nlohmann::json& r = run.report;
  if (!sim.finished) {
    r["verdict"] = "deadlock";
    r["deadlock"] = sim.deadlock;
    return run;
  }
  const Verdict v = check_against_golden(tree, queries, params, golden, sim.results, sim.visits);
  phases["check"] = since(t_phase);
  r["phase_seconds"] = phases;  // where the job's wall time went (prepare: tree, image, work estimate)
  run.match = v.match;
  r["verdict"] = v.match ? "match" : "mismatch";
  r["mismatches"] = {{"results", v.result_mismatches}, {"visits", v.visit_mismatches}, {"first", v.first}};
  run.search_seconds = static_cast<double>(sim.cycles) / (cfg.clock_mhz * 1e6);
  const double tree_bytes = mj.send_tree ? static_cast<double>(image.bytes.size()) : 0.0;
  const double query_bytes = 12.0 * static_cast<double>(queries.size());
  const double result_bytes =
      4.0 * static_cast<double>(queries.size()) + 8.0 * static_cast<double>(sim.results.neighbors.size());
  run.host_seconds = (mj.send_tree ? link_seconds(cfg, tree_bytes) : 0.0) + link_seconds(cfg, query_bytes) +
                     link_seconds(cfg, result_bytes);
  run.cycles = sim.cycles;
  run.energy_pj = sim.energy.at("total").get<double>();
  run.visits = sim.visits.visits;
  r["cycles"] = sim.cycles;
  r["top_height"] = tree.top_height;
  r["modeled_seconds"] = {{"search", run.search_seconds}, {"host", run.host_seconds},
                          {"total", run.search_seconds + run.host_seconds}};
  r["host_bytes"] = {{"tree", tree_bytes}, {"queries", query_bytes}, {"results", result_bytes}};
  r["energy_pj"] = run.energy_pj;
  r["neighbors"] = sim.results.neighbors.size();
  r["visits"] = visits_json(sim.visits);
  r["units"] = {{"ru_utilization", sim.units["recursion_units"]["utilization"]},
                {"su_utilization", sim.units["search_units"]["utilization"]}};
  r["wall_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.results = std::move(sim.results);
  return run;
}

}  // namespace tigris
