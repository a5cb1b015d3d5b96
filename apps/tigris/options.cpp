#include "options.hpp"

#include <cfloat>
#include <cmath>

#include <cstdio>
#include <map>
#include <stdexcept>

#include "core/arg_checks.hpp"
#include "testbench/presets.hpp"

namespace tigris {

void add_search_options(CLI::App& app, SearchOptions& o, bool replay) {
  input_flag(app.add_option("--cloud", o.cloud,
                            "Point cloud the KD-tree is built on: KITTI .bin, .pcd or .ply (default: the "
                            "built-in synthetic frame 0; without --queries the cloud is searched in itself)"));
  input_flag(app.add_option("--queries", o.queries,
                            "Query points, same formats; needs --cloud (default: the cloud itself, or with "
                            "neither flag the built-in synthetic frame 1, the same street scanned 1 m further "
                            "on and turned 1 degree)"));
  app.add_option("--seed", o.seed, "Seed of the built-in synthetic frames (0 .. 2^64-1)")
      ->capture_default_str()
      ->check(uint64_text());
  app.add_option("--mode", o.mode, "Search: nn, knn or radius")
      ->check(CLI::IsMember({"nn", "knn", "radius"}))
      ->capture_default_str();
  app.add_option("--k", o.k, "Neighbours per query for --mode knn")->capture_default_str();
  app.add_option("--radius", o.radius, "Radius in metres for --mode radius")
      ->check(finite_range(0.0, 1e30))
      ->capture_default_str();
  app.add_option("--max-nn", o.max_nn, "Radius search keeps only the max-nn nearest (0: all); visits are unchanged")
      ->capture_default_str();
  app.add_option("--height", o.height, "Top-tree height h: 0 (brute force) .. full; 'full' is the canonical KD-tree")
      ->capture_default_str();
  app.add_option("--split-axis", o.split_axis, "Split axis rule: widest (extent) or round-robin")
      ->check(CLI::IsMember({"widest", "round-robin"}))
      ->capture_default_str();
  app.add_option("--approx-thd", o.approx_thd,
                 "Approximate (leader/follower) search with this threshold in metres; 'default' "
                 "takes the paper's 1.2 m for nn/knn and 0.4 r for radius (default: exact)");
  app.add_option("--leader-scope", o.leader_scope,
                 "Where approximate search checks leaders: first_leaf (the paper authors' code: at a "
                 "query's first leaf; a follower takes its leader's final results and stops) or "
                 "every_leaf (the earlier reading: at every leaf, a leader's list local to the leaf)")
      ->check(CLI::IsMember({"first_leaf", "every_leaf"}))
      ->capture_default_str();
  app.add_option("--leader-in-flight", o.leader_in_flight,
                 "first_leaf: what a query's Leader Check sees of leaders still searching: wait (a "
                 "leader counts from its own check; its followers wait for its final results) or "
                 "finished_only (a leader counts once it has finished)")
      ->check(CLI::IsMember({"wait", "finished_only"}))
      ->capture_default_str();
  app.add_option("--leader-capacity", o.leader_capacity, "Leaders kept per leaf (approximate search)")
      ->capture_default_str();
  app.add_option("--leader-width", o.leader_width,
                 "Leader result width R for nn/knn (approximate search, every_leaf; 0: k)")
      ->capture_default_str();
  output_flag(app.add_option("--dump-results", o.dump_results,
                             "Write the results as CSV query,rank,index,dist2 (canonical order)"));
  output_flag(app.add_option("--dump-schedule", o.dump_schedule,
                             "Write the leaf-visit schedule as CSV seq,query,leaf,event (event: visit, or a "
                             "first_leaf leader's finish)"));
  if (replay) {
    input_flag(app.add_option("--schedule", o.schedule,
                              "Replay this leaf-visit schedule (CSV seq,query,leaf,event) instead of index order"));
    app.add_flag("--redundancy", o.redundancy,
                 "Also measure the two-stage tree's redundancy (paper section 4.1) under both conventions: "
                 "nodes visited against the canonical tree (the model's), and distance computations of the "
                 "authors' classic tree (points only in leaves, bounding-box pruning) with leaves as large as "
                 "this tree's leaf sets against leaves of one point; every search is checked against the "
                 "golden results (stats.json \"redundancy\")");
  }
  app.add_option("--max-work", o.limits.max_work,
                 "Refuse a run estimated (from a sample of queries) to compute more node and point "
                 "distances than this; 0: no limit")
      ->check(finite_range(0.0, 1e18))
      ->capture_default_str();
  app.add_option("--max-results", o.limits.max_results,
                 "Refuse a run estimated to return more neighbours than this (radius: before "
                 "--max-nn); 0: no limit")
      ->check(finite_range(0.0, 1e18))
      ->capture_default_str();
  app.add_option("--out", o.out, "Output folder for stats.json")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& s) -> std::string { return s.empty() ? "must name a folder, got an empty path" : ""; },
          "DIR"));
}

int default_height_for(int height, bool chosen, std::size_t points, const std::string& cloud_name) {
  const int full = full_height_for(points);
  if (height <= full) return height;
  if (chosen)
    throw std::invalid_argument(cloud_name + ": top height " + std::to_string(height) +
                                " (--height / tree.top_height) exceeds the full height " + std::to_string(full) +
                                " of its " + std::to_string(points) + "-point tree; use at most " +
                                std::to_string(full) + ", or full");
  std::fprintf(stderr,
               "tigris: note: %s has %zu points, so its full tree height is %d; the default top "
               "height %d is clamped to %d (pass --height to choose)\n",
               cloud_name.c_str(), points, full, height, full);
  return full;
}

void note_k_above_cloud(const char* command, const SearchParams& p, std::size_t points, const std::string& cloud_name) {
  if (p.mode == Mode::KNN && static_cast<std::size_t>(p.k) > points)
    std::fprintf(stderr,
                 "%s: note: --k %d is more than the %zu points of %s: every query returns all %zu of them, in "
                 "distance order\n",
                 command, p.k, points, cloud_name.c_str(), points);
}

SearchParams search_params(const CLI::App& app, const SearchOptions& o, LeaderScope scope, LeaderInFlight in_flight) {
  SearchParams p;
  p.mode = parse_mode(o.mode);
  if (app.count("--k") && p.mode != Mode::KNN)
    throw std::invalid_argument("--k applies to --mode knn only (nn is the k = 1 search)");
  if ((app.count("--radius") || app.count("--max-nn")) && p.mode != Mode::Radius)
    throw std::invalid_argument("--radius and --max-nn apply to --mode radius only");
  p.k = p.mode == Mode::KNN ? o.k : 1;
  // A radius below the smallest normal float would search with 0 (or a denormal) in the model.
  if (p.mode == Mode::Radius && o.radius < FLT_MIN) {
    char b[96];
    std::snprintf(b, sizeof b, "--radius must be > 0 metres (at least %g), got %g", double(FLT_MIN), o.radius);
    throw std::invalid_argument(b);
  }
  p.radius = static_cast<float>(o.radius);
  p.max_nn = o.max_nn;
  if (!o.approx_thd.empty()) {
    p.approximate = true;
    if (o.approx_thd == "default") {
      p.approx_thd = default_approx_thd(p);
    } else {
      std::string text = o.approx_thd;
      if (!finite_range(0.0, 1e30)(text).empty())
        throw std::invalid_argument("--approx-thd must be a number of metres from 0 to 1e30, or 'default', got '" +
                                    o.approx_thd + "'");
      p.approx_thd = static_cast<float>(std::strtod(o.approx_thd.c_str(), nullptr));
    }
  } else if (app.count("--leader-capacity") || app.count("--leader-width") || app.count("--leader-scope") ||
             app.count("--leader-in-flight")) {
    throw std::invalid_argument(
        "--leader-scope, --leader-in-flight, --leader-capacity and --leader-width need --approx-thd");
  }
  p.leader_scope = app.count("--leader-scope") ? parse_leader_scope(o.leader_scope) : scope;
  p.leader_in_flight = app.count("--leader-in-flight") ? parse_leader_in_flight(o.leader_in_flight) : in_flight;
  if (app.count("--leader-in-flight") && p.leader_scope != LeaderScope::FirstLeaf)
    throw std::invalid_argument(
        "--leader-in-flight applies to leader scope first_leaf (--leader-scope or leader.scope)");
  if (app.count("--leader-width") && p.leader_scope == LeaderScope::FirstLeaf)
    throw std::invalid_argument(
        "--leader-width applies to leader scope every_leaf (--leader-scope or leader.scope; "
        "first_leaf leaders keep their final results)");
  p.leader_capacity = o.leader_capacity;
  p.leader_width = o.leader_width;
  validate(p);
  return p;
}

namespace {
std::map<const CLI::Option*, std::string>& path_roles() {
  static std::map<const CLI::Option*, std::string> roles;
  return roles;
}
}  // namespace

CLI::Option* output_flag(CLI::Option* option) {
  path_roles()[option] = "output";
  return option->type_name("OUTPUT");
}

CLI::Option* input_flag(CLI::Option* option) {
  path_roles()[option] = "input";
  return option->type_name("FILE");
}

CLI::Validator preset_or_file() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        try {
          value = config_path(value);
          return "";
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
      },
      "FILE|PRESET", "preset or file");
}

nlohmann::json flags_json(const CLI::App& command) {
  nlohmann::json flags = nlohmann::json::array();
  for (const CLI::Option* opt : command.get_options()) {
    if (opt->get_lnames().empty()) continue;  // positional
    const bool takes_value = opt->get_expected_max() != 0;
    nlohmann::json f = {{"flag", opt->get_lnames().front()},
                        {"takes_value", takes_value},
                        {"type", takes_value ? opt->get_type_name() : ""},
                        {"default", opt->get_default_str()},
                        {"doc", opt->get_description()}};
    if (const auto it = path_roles().find(opt); it != path_roles().end())
      f["role"] = it->second;
    else if (f["flag"] == "out")
      f["role"] = "out_folder";
    flags.push_back(f);
  }
  return {{"command", command.get_name()}, {"flags", flags}};
}

}  // namespace tigris
