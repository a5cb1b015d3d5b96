#include "run_record.hpp"

#include <cstdio>
#include <stdexcept>

#include "bottleneck.hpp"
#include "config.hpp"
#include "report.hpp"
#include "run_inputs.hpp"
#include "run_report.hpp"
#include "sampling.hpp"
#include "stat_formulas.hpp"

namespace tigris {

// The configuration as stats.json records it: the accelerator's keys, and the search and
// approximation settings of this run. Its SHA-256 identifies the configuration in every output.
nlohmann::json run_config_json(const RunSetup& r) {
  nlohmann::json config = config_to_json(r.p.cfg);
  const nlohmann::json search_config = search_config_json(r.params, r.p.tree);
  config["search"] = search_config["search"];
  config["approx"] = search_config["approx"];  // the threshold and leader width of this run
  return config;
}

// The stats JSON (docs/stats.md): the run, the accelerator's statistics, the derived fields from
// their formulas, the bottleneck and the configuration that produced them.
nlohmann::json run_stats(const RunSetup& r, const JobOutcome& m, const std::string& command_line, Accuracy& accuracy) {
  const SearchOutput& hw_view = m.sim.visits;
  nlohmann::json stats;
  stats["command"] = "run";
  stats["command_line"] = command_line;
  stats["inputs"] = r.inputs;
  stats["workload"] = {{"cloud", r.w.cloud_name}, {"queries", r.w.queries_name}, {"points", r.w.cloud.size()}};
  stats["cycles"] = m.sim.cycles;  // sampled: the estimate (sampling says how it was made)
  stats["cycles_ci95"] = m.sim.sampling["cycles_ci95"];
  stats["sampling"] = m.sim.sampling;
  stats["queries"] = r.w.queries.size();
  stats["verdict"] = m.verdict.match ? "match" : "mismatch";
  stats["mismatches"] = {
      {"results", m.verdict.result_mismatches}, {"visits", m.verdict.visit_mismatches}, {"first", m.verdict.first}};
  stats["visits"] = visits_json(hw_view);
  if (r.params.approximate) {
    accuracy = measure_accuracy(r.params.mode, m.golden.results, m.sim.results);
    stats["leaders"] = leaders_json(hw_view);
    stats["accuracy"] = accuracy_json(accuracy);
  }
  stats["units"] = m.sim.units;
  stats["buffers"] = m.sim.buffers;
  stats["energy_pj"] = m.sim.energy;
  stats["area_mm2"] = m.sim.area;
  stats["latency_cycles"] = m.sim.latency;
  stats["config"] = run_config_json(r);
  const nlohmann::json prov = provenance_json(command_line, r.inputs, stats["config"]);
  stats["config_sha256"] = prov["config_sha256"];
  stats["commit"] = prov["commit"];
  add_derived(stats);
  stats["tree"] = tree_json(r.p.tree);  // the bound names what the hottest Point Buffer banks hold
  stats["bottleneck"] = bottleneck_json(stats);
  stats["wall_seconds"] = {{"golden", m.golden_seconds}, {"simulation", m.sim_seconds}};
  if (const std::string bad = non_finite_field(stats); !bad.empty())
    throw std::invalid_argument("the model computed a non-finite " + bad +
                                " (NaN or infinity) from this configuration; check the energy.*, area.* and "
                                "cost.* keys that feed it (tigris run --list-config)");
  return stats;
}

// The summary lines of a run on stdout.
void print_run_summary(const RunSetup& r, const JobOutcome& m, const nlohmann::json& stats, const Accuracy& accuracy,
                       const std::string& stats_path) {
  const hw::AcceleratorConfig& cfg = r.p.cfg;
  const SearchParams& params = r.params;
  const SearchOutput& hw_view = m.sim.visits;
  const auto& u = stats["units"];
  const bool sampled = stats["sampling"]["sampled"].get<bool>();
  std::printf("tigris run: %s search of %zu queries in %zu points: %s\n", to_string(params.mode), r.w.queries.size(),
              r.w.cloud.size(), m.verdict.match ? "MATCH (every query bit-exact)" : "MISMATCH");
  std::fputs(inputs_summary(stats["inputs"]).c_str(), stdout);
  std::printf("  config  %d RU, %d SU x %d PE (%s, Node Cache %s), top height %d of %d, %.0f MHz\n",
              cfg.fe.recursion_units, cfg.be.search_units, cfg.be.pes_per_su, cfg.be.issue_policy.c_str(),
              cfg.node_cache.bytes == 0 ? "off" : cfg.node_cache.policy.c_str(), r.p.tree.top_height,
              r.p.tree.full_height, cfg.clock_mhz);
  std::printf("  cycles  %s%llu (%.3f ms at %.0f MHz); lower bound %.0f\n", sampled ? "~" : "",
              static_cast<unsigned long long>(m.sim.cycles), stats["seconds"].get<double>() * 1e3, cfg.clock_mhz,
              stats["lower_bound_cycles"].get<double>());
  std::fputs(sampling_summary(stats["sampling"]).c_str(), stdout);
  std::printf("  bound   %s\n", stats["bottleneck"]["summary"].get<std::string>().c_str());
  std::printf("  units   RU utilization %.1f%%, SU utilization %.1f%%, PE utilization %.1f%%\n",
              100 * u["recursion_units"]["utilization"].get<double>(),
              100 * u["search_units"]["utilization"].get<double>(),
              100 * u["search_units"]["pe_utilization"].get<double>());
  std::printf("  visits  top %llu, pruned %llu, leaf points %llu\n",
              static_cast<unsigned long long>(hw_view.visits.top),
              static_cast<unsigned long long>(hw_view.visits.pruned),
              static_cast<unsigned long long>(hw_view.visits.leaf_points));
  const auto& lat = m.sim.latency;
  std::printf(
      "  latency query mean %.0f, p50 %llu, p99 %llu, max %llu cycles; BQB wait mean %.0f, p99 %llu, max %llu%s\n",
      lat["query"]["mean"].get<double>(), lat["query"]["p50"].get<unsigned long long>(),
      lat["query"]["p99"].get<unsigned long long>(), lat["query"]["max"].get<unsigned long long>(),
      lat["bqb_wait"]["mean"].get<double>(), lat["bqb_wait"]["p99"].get<unsigned long long>(),
      lat["bqb_wait"]["max"].get<unsigned long long>(), sampled ? " (of the simulated queries)" : "");
  if (params.approximate) {
    std::printf(
        "  approx  thd %.3g m, capacity %d: %llu leaders, %llu followers, %llu buffer-full; "
        "leader checks %llu, follower points %llu\n",
        static_cast<double>(params.approx_thd), params.leader_capacity,
        static_cast<unsigned long long>(hw_view.leaders.leaders),
        static_cast<unsigned long long>(hw_view.leaders.followers),
        static_cast<unsigned long long>(hw_view.leaders.leader_buffer_full),
        static_cast<unsigned long long>(hw_view.visits.leader_checks),
        static_cast<unsigned long long>(hw_view.visits.follower_points));
    if (params.mode == Mode::Radius)
      std::printf("  accuracy vs exact: recall %.4f, precision %.4f, %.1f%% of queries exact\n", accuracy.recall(),
                  accuracy.precision(), 100 * accuracy.exact_match_fraction());
    else
      std::printf("  accuracy vs exact: %.1f%% of queries exact, extra distance mean %.4f m, max %.3f m\n",
                  100 * accuracy.exact_match_fraction(), accuracy.mean_extra_m, accuracy.max_extra_m);
  }
  std::fputs(energy_area_summary(stats).c_str(), stdout);
  std::printf("  time    simulation %.2f s, golden model %.2f s\n  stats   %s\n", m.sim_seconds, m.golden_seconds,
              stats_path.c_str());
}

}  // namespace tigris
