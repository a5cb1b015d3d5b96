#include "accel_job.hpp"

#include <chrono>
#include <exception>
#include <stdexcept>
#include <thread>
#include <utility>

#include "config.hpp"
#include "core/timer.hpp"
#include "hw/job.hpp"
#include "hw/mem/result_slots.hpp"
#include "report.hpp"
#include "sampling.hpp"
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

BuiltTree BuiltTree::of(const PointCloud& points, int top_height, SplitRule split) {
  BuiltTree b;
  b.tree = build_kdtree(points, top_height, split);
  b.image = tlm_if::encode_tree_image(b.tree);
  return b;
}

PreparedJob prepare_job(const PointCloud& points, const PointCloud& queries, const SearchParams& params,
                        const hw::AcceleratorConfig& cfg, const WorkLimits& limits, const std::string& fit_prefix,
                        BuiltTree* built) {
  PreparedJob p;
  p.cfg = cfg;
  BuiltTree own;
  if (!built || !built->fits(points, cfg))
    own = BuiltTree::of(points, cfg.tree.top_height, cfg.tree.split_axis), built = &own;
  p.tree = std::move(built->tree);
  p.image = std::move(built->image);
  p.job = host_job(params);
  const std::string fit = hw::job_fit_error(cfg, p.image.bytes.size(), queries.size(), p.tree.top_height, p.job.mode,
                                            p.job.k, p.job.approximate && p.job.first_leaf);
  if (!fit.empty()) throw std::invalid_argument(fit_prefix + fit);
  p.estimate = estimate_work(p.tree, queries, params);
  if (params.mode != Mode::Radius)
    add_slot_traffic(p.estimate, queries.size(), hw::ResultSlots::slot_bytes(p.job.k), cfg.sram.results.word_bytes);
  check_work(p.estimate, limits, queries.size());
  return p;
}

namespace {

// The golden model's figures of the sampled queries `ids`, in their order.
SearchOutput golden_of(const SearchOutput& golden, const std::vector<std::uint32_t>& ids) {
  SearchOutput g;
  for (std::uint32_t q : ids) {
    g.results.append_query(golden.results.begin(q), golden.results.end(q));
    g.per_query.push_back(golden.per_query[q]);
  }
  return g;
}

// A sampled job's results and visits: the simulated queries' as the accelerator gave them,
// the others' as the golden model did.
void merge_sample(const SearchOutput& golden, const std::vector<std::uint32_t>& ids, SimOutcome& sim) {
  // A mismatch report may come from output of another shape: keep it as the accelerator left it.
  if (sim.results.num_queries() != ids.size() || sim.visits.per_query.size() != ids.size()) return;
  for (const ScheduleEntry& e : sim.visits.schedule)
    if (e.query >= ids.size()) return;
  std::vector<std::uint32_t> at(golden.per_query.size(), ~0u);  // query -> its stream position
  for (std::uint32_t i = 0; i < ids.size(); ++i) at[ids[i]] = i;
  Results results;
  results.neighbors.reserve(golden.results.neighbors.size());
  SearchOutput visits;
  for (std::uint32_t q = 0; q < at.size(); ++q) {
    const bool simulated = at[q] != ~0u;
    const Results& from = simulated ? sim.results : golden.results;
    const std::size_t i = simulated ? at[q] : q;
    results.append_query(from.begin(i), from.end(i));
    const QueryVisits& v = simulated ? sim.visits.per_query[i] : golden.per_query[q];
    visits.per_query.push_back(v);
    visits.visits.add(v);
  }
  visits.schedule = std::move(sim.visits.schedule);
  for (ScheduleEntry& e : visits.schedule) e.query = ids[e.query];
  sim.results = std::move(results);
  sim.visits = std::move(visits);
}

}  // namespace

SamplingPlan job_plan(const PreparedJob& p, const SearchParams& params, std::size_t queries) {
  return plan_sampling(p.cfg.sim, static_cast<std::uint32_t>(queries),
                       static_cast<std::uint32_t>(hw::queries_in_flight(p.cfg, p.tree.top_height, p.job.mode, p.job.k,
                                                                        p.job.approximate, p.job.first_leaf, queries)),
                       params.approximate);
}

void check_every_query(const SamplingPlan& plan, bool waves, const std::string& every_query) {
  if (!plan.sampled) return;
  if (waves)
    throw std::invalid_argument(
        "waveforms and timelines show every query, and sampled simulation (sim.sampling) simulates a part: set "
        "sim.sampling=off for them");
  if (!every_query.empty())
    throw std::invalid_argument(every_query + " needs every query simulated, and sampled simulation (sim.sampling) " +
                                "simulates " + std::to_string(plan.stream.size()) + " of " +
                                std::to_string(plan.queries) + ": set sim.sampling=off for it");
}

JobOutcome run_job(const PreparedJob& p, const PointCloud& points, const PointCloud& queries,
                   const SearchParams& params, const SimExtras& extras) {
  JobOutcome m;
  SearchParams exact = params;
  exact.approximate = false;
  const auto golden = [&] {
    const auto t0 = std::chrono::steady_clock::now();
    m.golden = golden_search(p.tree, queries, exact);
    m.golden_seconds = seconds_since(t0);
  };
  const SamplingPlan plan = job_plan(p, params, queries.size());
  check_every_query(plan, !extras.vcd_path.empty() || !extras.observers.empty(), extras.every_query);
  PointCloud stream;  // sampled: the queries simulated
  for (std::uint32_t q : plan.stream) stream.push_back(queries[q]);

  SimSetup setup;
  setup.config = p.cfg;
  setup.image = &p.image;
  setup.queries = plan.sampled ? &stream : &queries;
  setup.num_points = static_cast<std::uint32_t>(points.size());
  setup.job = p.job;
  setup.vcd_path = extras.vcd_path;
  setup.gtkw_path = extras.gtkw_path;
  setup.provenance = extras.provenance;
  setup.observers = extras.observers;
  setup.sim_threads = extras.sim_threads;
  if (plan.sampled) {  // the seams' warming needs each query's result count first
    golden();
    setup.sampling = &plan;
    for (std::size_t q = 0; q < queries.size(); ++q) {
      const QueryVisits& v = m.golden.per_query[q];
      setup.sampling_work.records.push_back(static_cast<std::uint32_t>(m.golden.results.count(q)));
      setup.sampling_work.leaf_points.push_back(v.leaf_points);
      setup.sampling_work.top_nodes.push_back(v.top + v.pruned);
    }
  }
  // The simulation on a thread of its own (SystemC's stack switches confuse the sanitizers'
  // view of the main thread); a full simulation's golden search meanwhile on this one.
  std::exception_ptr sim_failure, golden_failure;
  std::thread sim([&] {
    try {
      const auto t0 = std::chrono::steady_clock::now();
      m.sim = std::move(simulate({setup}, extras.progress).front());  // (front() of a temporary: a copy)
      m.sim_seconds = seconds_since(t0);
    } catch (...) {
      sim_failure = std::current_exception();
    }
  });
  if (!plan.sampled) {
    try {
      golden();
    } catch (...) {
      golden_failure = std::current_exception();
    }
  }
  sim.join();
  if (sim_failure) std::rethrow_exception(sim_failure);
  if (golden_failure) std::rethrow_exception(golden_failure);
  if (!m.sim.error.empty()) throw std::invalid_argument(m.sim.error);
  if (!plan.sampled) m.sim.sampling = full_simulation_json(plan, m.sim.cycles);
  const auto t0 = std::chrono::steady_clock::now();
  if (m.sim.finished) {
    if (plan.sampled) {
      m.verdict = check_against_golden(p.tree, stream, params, golden_of(m.golden, plan.stream), m.sim.results,
                                       m.sim.visits, 5, &plan.stream);
      merge_sample(m.golden, plan.stream, m.sim);
    } else {
      m.verdict = check_against_golden(p.tree, queries, params, m.golden, m.sim.results, m.sim.visits);
    }
  }
  m.check_seconds = seconds_since(t0);
  return m;
}

ModelJobRun run_model_job(const ModelJob& mj, hw::AcceleratorConfig cfg, const WorkLimits& limits, int sim_threads) {
  auto t_phase = std::chrono::steady_clock::now();
  const auto t0 = t_phase;
  nlohmann::json phases;
  const PointCloud& queries = *mj.queries;
  const SearchParams& params = mj.params;
  cfg.tree.top_height = std::min(mj.top_height, full_height_for(mj.points->size()));
  if (params.approximate)
    cfg.leader.capacity_per_leaf = params.leader_capacity, cfg.leader.width = params.leader_width,
    cfg.leader.scope = params.leader_scope, cfg.leader.in_flight = params.leader_in_flight;
  validate_config(cfg);
  const PreparedJob p =
      prepare_job(*mj.points, queries, params, cfg, limits, "does not fit the accelerator: ", mj.built);
  phases["prepare"] = since(t_phase);
  SimExtras extras;
  extras.sim_threads = sim_threads;
  JobOutcome m = run_job(p, *mj.points, queries, params, extras);
  phases["golden"] = m.golden_seconds;
  phases["simulate"] = m.sim_seconds;
  ModelJobRun run;
  nlohmann::json& r = run.report;
  if (!m.sim.finished) {
    r["verdict"] = "deadlock";
    r["deadlock"] = m.sim.deadlock;
    return run;
  }
  SimOutcome& sim = m.sim;
  const Verdict& v = m.verdict;
  phases["check"] = m.check_seconds;
  r["phase_seconds"] = phases;  // where the job's wall time went (prepare: tree, image, work estimate)
  run.match = v.match;
  r["verdict"] = v.match ? "match" : "mismatch";
  r["mismatches"] = {{"results", v.result_mismatches}, {"visits", v.visit_mismatches}, {"first", v.first}};
  run.search_seconds = static_cast<double>(sim.cycles) / (cfg.clock_mhz * 1e6);
  const double tree_bytes = mj.send_tree ? static_cast<double>(p.image.bytes.size()) : 0.0;
  const double query_bytes = 12.0 * static_cast<double>(queries.size());
  const double result_bytes =
      4.0 * static_cast<double>(queries.size()) + 8.0 * static_cast<double>(sim.results.neighbors.size());
  run.host_seconds = (mj.send_tree ? link_seconds(cfg, tree_bytes) : 0.0) + link_seconds(cfg, query_bytes) +
                     link_seconds(cfg, result_bytes);
  run.cycles = sim.cycles;
  run.energy_pj = sim.energy.at("total").get<double>();
  run.visits = sim.visits.visits;
  r["cycles"] = sim.cycles;
  r["cycles_ci95"] = sim.sampling["cycles_ci95"];
  r["sampling"] = sim.sampling;
  r["top_height"] = p.tree.top_height;
  r["modeled_seconds"] = {
      {"search", run.search_seconds}, {"host", run.host_seconds}, {"total", run.search_seconds + run.host_seconds}};
  r["host_bytes"] = {{"tree", tree_bytes}, {"queries", query_bytes}, {"results", result_bytes}};
  r["energy_pj"] = run.energy_pj;
  r["neighbors"] = sim.results.neighbors.size();
  r["visits"] = visits_json(sim.visits);
  r["units"] = {{"ru_utilization", sim.units["recursion_units"]["utilization"]},
                {"su_utilization", sim.units["search_units"]["utilization"]}};
  r["wall_seconds"] = seconds_since(t0);
  run.results = std::move(sim.results);
  return run;
}

}  // namespace tigris
