#include "ref_command.hpp"
#include "command.hpp"

#include "testbench/run_inputs.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "core/arg_checks.hpp"
#include "core/progress.hpp"
#include "core/timer.hpp"
#include "sw_ref/classic_tree.hpp"
#include "sw_ref/stats.hpp"
#include "testbench/report.hpp"
#include "traces/schedule_csv.hpp"
#include "workloads/workload.hpp"

namespace tigris {

namespace {

// Another tree's results must be the golden model's, bit for bit: a redundancy counted on a
// search that answers differently would be no measurement at all.
void check_same_results(const Results& golden, const Results& other, const std::string& what) {
  if (const auto diff = first_difference(golden, other))
    throw std::runtime_error("--redundancy: the " + what + " answers differently from the golden model: " + *diff);
}

// The two-stage tree's redundancy (paper section 4.1) under both conventions (docs/model.md):
//  - the model's: nodes visited per query (top-tree nodes + leaf-set points) against the
//    canonical tree (a point in every node, split-plane pruning);
//  - the authors' (horizon-research/PointCloud-pipeline, kdtree.h): distance computations of
//    the classic tree (points only in leaves, bounding-box pruning) with leaves of at most
//    ceil(n / 2^h) points, against leaves of one point.
nlohmann::json redundancy_json(const KdTree& tree, const SearchOutput& out, const Workload& w,
                               const SearchParams& params, SplitRule split, bool self) {
  const double nq = std::max<double>(1.0, static_cast<double>(w.queries.size()));
  const KdTree canonical = build_kdtree(w.cloud, full_height_for(w.cloud.size()), split);
  const SearchOutput c = search(canonical, w.queries, params);
  check_same_results(out.results, c.results, "canonical tree");
  const double two_stage = static_cast<double>(out.visits.top + out.visits.leaf_points) / nq;
  const double canon = static_cast<double>(c.visits.top + c.visits.leaf_points) / nq;

  const std::uint32_t leaf_max = classic_leaf_max_for_height(w.cloud.size(), tree.top_height);
  const ClassicTree big = build_classic_tree(w.cloud, leaf_max), one = build_classic_tree(w.cloud, 1);
  const ClassicOutput b = classic_search(big, w.queries, params), o = classic_search(one, w.queries, params);
  check_same_results(out.results, b.results, "classic tree of leaves of at most " + std::to_string(leaf_max));
  check_same_results(out.results, o.results, "classic tree of leaves of one point");
  const double ratio_model = canon > 0 ? two_stage / canon : 0.0;
  const double ratio_authors = o.dist > 0 ? static_cast<double>(b.dist) / static_cast<double>(o.dist) : 0.0;
  return {{"model",
           {{"convention",
             "nodes visited (top-tree nodes + leaf-set points) of this two-stage tree against the "
             "canonical tree (a point in every node)"},
            {"two_stage_per_query", two_stage},
            {"canonical_per_query", canon},
            {"ratio", ratio_model}}},
          {"authors",
           {{"convention",
             "distance computations of the classic tree (points only in leaves, bounding-box "
             "pruning; horizon-research/PointCloud-pipeline kdtree.h) with leaves of at most "
             "leaf_max points against leaves of one point"},
            {"leaf_max", leaf_max},
            {"leaves", big.num_leaves},
            {"leaf_mean", big.num_leaves ? static_cast<double>(w.cloud.size()) / big.num_leaves : 0.0},
            {"per_query", static_cast<double>(b.dist) / nq},
            {"leaf_one_per_query", static_cast<double>(o.dist) / nq},
            {"leaves_scanned_per_query", static_cast<double>(b.leaves) / nq},
            {"ratio", ratio_authors}}},
          {"queries", self ? "the cloud itself" : "another frame"}};
}

}  // namespace

int run_ref_command(const CLI::App& app, const SearchOptions& o) {
  check_distinct_paths({{"--cloud", o.cloud}, {"--queries", o.queries}, {"--schedule", o.schedule}},
                       {{"--out (stats.json)", o.out + "/stats.json"},
                        {"--dump-results", o.dump_results},
                        {"--dump-schedule", o.dump_schedule}});
  const SearchParams params = search_params(app, o);
  if (o.redundancy && (params.approximate || !o.schedule.empty()))
    throw std::invalid_argument("--redundancy counts exact searches: it does not go with " +
                                std::string(params.approximate ? "--approx-thd" : "--schedule"));
  int height = parse_height(o.height);
  const SplitRule split = parse_split_rule(o.split_axis);
  Schedule replay;
  if (!o.schedule.empty()) replay = read_schedule_csv(o.schedule);

  const Workload w = load_workload(o.cloud, o.queries, o.seed);
  note_k_above_cloud("tigris ref", params, w.cloud.size(), w.cloud_name);
  height = default_height_for(height, app.count("--height") > 0, w.cloud.size(), w.cloud_name);
  auto t0 = std::chrono::steady_clock::now();
  const KdTree tree = build_kdtree(w.cloud, height, split);
  const double build_s = seconds_since(t0);
  check_work(estimate_work(tree, w.queries, params), o.limits, w.queries.size());
  const nlohmann::json inputs = search_inputs(o.cloud, o.queries, w.cloud_name, w.queries_name, "");
  FolderSpec spec{"ref", {}, nlohmann::json::object(), inputs, {"stats.json"}, false, {}};
  spec.named = {{"--dump-results", o.dump_results}, {"--dump-schedule", o.dump_schedule}};
  OutFolder folder(o.out, spec);
  ProgressReporter progress(o.schedule.empty() ? "tigris ref: queries" : "tigris ref: schedule rows");
  t0 = std::chrono::steady_clock::now();
  SearchOutput out;
  try {
    out = search(tree, w.queries, params, o.schedule.empty() ? nullptr : &replay, std::ref(progress));
  } catch (const ScheduleError& e) {  // a schedule that does not fit these queries: name the file
    throw ScheduleError(o.schedule + ": " + e.what());
  }
  const double search_s = seconds_since(t0);

  nlohmann::json stats;
  stats["command"] = "ref";
  stats["command_line"] = o.command_line;
  stats["inputs"] = inputs;
  stats["workload"] = {{"cloud", w.cloud_name}, {"queries", w.queries_name}, {"points", w.cloud.size()}};
  stats["queries"] = w.queries.size();
  stats["config"] = search_config_json(params, tree);
  stats["tree"] = tree_json(tree);
  stats["visits"] = visits_json(out);
  if (params.approximate) stats["leaders"] = leaders_json(out);
  stats["results"] = {{"neighbors", out.results.neighbors.size()}};
  stats["schedule"] = {{"source", o.schedule.empty() ? "query index order" : o.schedule},
                       {"leaf_visits", out.visits.leaf_visits}};
  stats["wall_seconds"] = {{"build", build_s}, {"search", search_s}};
  if (o.redundancy) {
    t0 = std::chrono::steady_clock::now();
    const bool self = !o.cloud.empty() && (o.queries.empty() || o.queries == o.cloud);
    stats["redundancy"] = redundancy_json(tree, out, w, params, split, self);
    stats["wall_seconds"]["redundancy"] = seconds_since(t0);
  }
  folder.check_inputs();
  const std::string stats_path = o.out + "/stats.json";
  write_file(stats_path, [&](std::ostream& f) {
    f << stats.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
  });
  if (!o.dump_results.empty())
    folder.write(o.dump_results, [&](std::ostream& f) { write_results_csv(f, out.results); });
  if (!o.dump_schedule.empty())
    folder.write(o.dump_schedule, [&](std::ostream& f) { write_schedule_csv(f, out.schedule); });

  const double nq = static_cast<double>(w.queries.size());
  const auto& v = out.visits;
  std::printf("tigris ref: %s%s search of %zu queries in %zu points\n", to_string(params.mode),
              params.approximate ? " (approximate)" : "", w.queries.size(), w.cloud.size());
  std::fputs(inputs_summary(stats["inputs"]).c_str(), stdout);
  std::printf("  tree    top height %d of %d (%s split), %u leaves, mean leaf set %.1f\n", tree.top_height,
              tree.full_height, to_string(split), tree.num_leaves(), stats["tree"]["leaf_set_mean"].get<double>());
  std::printf("  time    build %.3f s, search %.3f s (%.0f queries/s)\n", build_s, search_s,
              search_s > 0 ? nq / search_s : 0.0);
  std::printf("  visits  top %llu, pruned %llu, leaf points %llu (per query %.1f / %.1f / %.1f)\n",
              static_cast<unsigned long long>(v.top), static_cast<unsigned long long>(v.pruned),
              static_cast<unsigned long long>(v.leaf_points), v.top / nq, v.pruned / nq, v.leaf_points / nq);
  if (params.approximate)
    std::printf(
        "  approx  thd %.3g m: %llu leaders, %llu followers, %llu buffer-full; "
        "leader checks %llu, follower points %llu\n",
        static_cast<double>(params.approx_thd), static_cast<unsigned long long>(out.leaders.leaders),
        static_cast<unsigned long long>(out.leaders.followers),
        static_cast<unsigned long long>(out.leaders.leader_buffer_full),
        static_cast<unsigned long long>(v.leader_checks), static_cast<unsigned long long>(v.follower_points));
  if (o.redundancy) {
    const auto& r = stats["redundancy"];
    std::printf(
        "  redundancy  model's convention %.2fx (%.1f nodes/query, canonical tree %.1f); authors' "
        "convention %.2fx (classic tree, leaves of at most %u points: %.1f distances/query, leaves of one "
        "point %.1f); all answers equal the golden model's\n",
        r["model"]["ratio"].get<double>(), r["model"]["two_stage_per_query"].get<double>(),
        r["model"]["canonical_per_query"].get<double>(), r["authors"]["ratio"].get<double>(),
        r["authors"]["leaf_max"].get<unsigned>(), r["authors"]["per_query"].get<double>(),
        r["authors"]["leaf_one_per_query"].get<double>());
  }
  std::printf("  results %zu neighbours\n  stats   %s\n", out.results.neighbors.size(), stats_path.c_str());
  folder.finish();
  return 0;
}

namespace {

const CommandRegistration kRegistration{options_command<SearchOptions>(
    "ref", "Run the golden software model only: KD-tree search with visit counts", 10,
    [](CLI::App& app, SearchOptions& o) {
      o.out = "tigris-out/ref";
      add_search_options(app, o, true);
    },
    [](const CLI::App& app, SearchOptions& o, const CommandLine& line) {
      o.command_line = line.text;
      return run_ref_command(app, o);
    })};

}  // namespace
}  // namespace tigris
