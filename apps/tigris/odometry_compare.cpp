// `tigris odometry --compare` ("the accelerator over a sequence"): the same sequence
// registered with PCL's FLANN, the golden model's exact and approximate search on the CPU, and
// the accelerator model in the loop, each a `tigris odometry` of its own in OUT/<back-end>/
// (resumable, --jobs or --slurm as given), then one table: KD-tree time (measured on the CPU,
// modeled for the accelerator), end to end and its reduction against FLANN, KD-tree energy, and
// KITTI's errors, with the approximate search's accuracy against the exact one. The CPU
// back-ends run --repeat times, interleaved (OUT/<back-end>-repeat-k/), and their times are
// medians with min and max, as in register --compare (cpu_baseline.hpp).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/children.hpp"
#include "core/json_file.hpp"
#include "odometry_command.hpp"
#include "registration/search_backends.hpp"
#include "testbench/cpu_baseline.hpp"
#include "testbench/report.hpp"

namespace tigris {
namespace {

using nlohmann::ordered_json;

using Backend = registration::SearchBackend;
// The back-ends compared, in the table's order (registration/search_backends.hpp).
const std::vector<Backend> kBackends = {registration::search_backend("flann"), registration::search_backend("exact"),
                                        registration::search_backend("approx"), registration::search_backend("accel")};

double at(const ordered_json& j, std::initializer_list<const char*> path) {
  const ordered_json* p = &j;
  for (const char* k : path) {
    if (!p->is_object() || !p->contains(k)) return NAN;
    p = &(*p)[k];
  }
  return p->is_number() ? p->get<double>() : NAN;
}

ordered_json number(double x) { return std::isfinite(x) ? ordered_json(x) : ordered_json(); }

std::string cell(double x, const char* fmt) {
  if (!std::isfinite(x)) return "-";
  char b[32];
  std::snprintf(b, sizeof b, fmt, x);
  return b;
}

}  // namespace

std::vector<OdometryOptions> compare_variants(const OdometryOptions& o) {
  std::vector<OdometryOptions> v;
  for (const Backend& b : kBackends) {
    OdometryOptions x = o;
    x.compare = false;
    x.search = b.search;
    if (!b.approximate) x.approx_thd.clear();
    if (!b.in_loop()) {
      x.accel_config.clear();
      x.accel_sets.clear();
    }
    v.push_back(x);
  }
  return v;
}

namespace {

// Every back-end's runs: metrics.json of each run (run 1 first), per back-end.
struct Runs {
  std::vector<std::vector<ordered_json>> metrics;
  std::vector<std::string> first_out;  // run 1's folder, per back-end
  int worst = 0;                       // the highest exit code (1: a pair not converged)
};

// Runs each back-end's `tigris odometry` as a child, the CPU ones --repeat times, interleaved.
Runs run_backends(const OdometryOptions& o) {
  Runs runs;
  std::vector<std::vector<ordered_json>>& metrics = runs.metrics;
  metrics.resize(kBackends.size());
  for (int k = 1; k <= o.repeat; ++k)
    for (std::size_t i = 0; i < kBackends.size(); ++i) {
      const Backend& b = kBackends[i];
      if (k > 1 && !b.cpu) continue;
      const std::string search = b.search,
                        out = o.out + "/" + search + (k == 1 ? std::string() : "-repeat-" + std::to_string(k));
      std::vector<std::string> drop{"--out", "--search", "--sequence", "--synthetic", "--seed", "--repeat"};
      if (!b.approximate) drop.push_back("--approx-thd");
      if (!b.in_loop()) drop.insert(drop.end(), {"--accel-config", "--accel-set"});
      std::fprintf(
          stderr, "tigris odometry --compare: %s%s (--search %s --out %s)\n", b.label,
          b.cpu && o.repeat > 1 ? (", run " + std::to_string(k) + " of " + std::to_string(o.repeat)).c_str() : "",
          b.search, out.c_str());
      const int code = wait_child(start_child(
          rerun_args(o.argv, {"--compare"}, drop, {"--sequence", o.sequence, "--search", search, "--out", out})));
      if (code != 0 && code != 1)
        throw std::invalid_argument("--compare: the " + search + " run failed (exit " + std::to_string(code) +
                                    "; its message is above); a rerun resumes");
      runs.worst = std::max(runs.worst, code);
      metrics[i].push_back(parse_json_text(read_input(out + "/metrics.json", "a back-end's metrics", kMaxSettingsBytes),
                                           out + "/metrics.json"));
      if (k == 1) runs.first_out.push_back(out);
      // The back-ends are deterministic: a repeat with other poses is a bug, not noise.
      const double a = at(metrics[i].back(), {"ate", "rmse_m"}), f = at(metrics[i].front(), {"ate", "rmse_m"});
      if (!(a == f || (std::isnan(a) && std::isnan(f))))
        throw std::runtime_error("--compare: the " + search + " back-end's run " + std::to_string(k) +
                                 " chained other poses than its run 1 (ATE " + std::to_string(a) + " m against " +
                                 std::to_string(f) + " m): the registration is not deterministic");
    }
  return runs;
}

// One row per back-end (comparison.json's "rows"); times gets each back-end's KD-tree and end-to-end
// spread (empty: no figure), timed the CPU back-ends' KD-tree spreads for the baseline's warnings.
ordered_json backend_rows(const Runs& runs, std::vector<std::pair<Spread, Spread>>& times,
                          std::vector<std::pair<std::string, Spread>>& timed) {
  ordered_json rows = ordered_json::array();
  for (std::size_t i = 0; i < kBackends.size(); ++i) {
    const Backend& b = kBackends[i];
    const ordered_json& m = runs.metrics[i].front();
    const bool accel = b.in_loop();
    std::vector<double> kd, e2e;
    for (const ordered_json& x : runs.metrics[i]) {
      kd.push_back(accel ? at(x, {"accelerator", "modeled_kdtree_seconds"})
                         : at(x, {"totals", "kdtree_search_seconds"}));
      e2e.push_back(accel ? at(x, {"accelerator", "modeled_end_to_end_seconds"}) : at(x, {"totals", "seconds"}));
    }
    const auto spread = [](const std::vector<double>& v) {
      for (double x : v)
        if (!std::isfinite(x)) return Spread{NAN, NAN, NAN, {}};
      return spread_of(v);
    };
    times.emplace_back(spread(kd), spread(e2e));
    if (b.cpu && !times.back().first.samples.empty())
      timed.emplace_back(std::string(b.search) + "'s KD-tree time", times.back().first);
    ordered_json r;
    r["back_end"] = b.search;
    r["label"] = b.label;
    r["runs"] = runs.metrics[i].size();
    r["kdtree_seconds"] = number(times.back().first.median);
    r["end_to_end_seconds"] = number(times.back().second.median);
    r["kdtree_seconds_spread"] = times.back().first.samples.empty() ? ordered_json() : to_json(times.back().first);
    r["end_to_end_seconds_spread"] =
        times.back().second.samples.empty() ? ordered_json() : to_json(times.back().second);
    r["timing"] = accel ? "modeled (the accelerator's jobs; the rest measured on this CPU, once)"
                        : "measured on this CPU: the median of the runs";
    r["kdtree_energy_pj"] = accel ? number(at(m, {"accelerator", "kdtree_energy_pj"})) : ordered_json();
    r["not_converged_pairs"] = m.value("not_converged_pairs", 0);
    r["t_err_percent"] = number(at(m, {"kitti", "t_err_percent"}));
    r["r_err_deg_per_m"] = number(at(m, {"kitti", "r_err_deg_per_m"}));
    r["ate_rmse_m"] = number(at(m, {"ate", "rmse_m"}));
    r["mean_rpe_translation_m"] = number(at(m, {"rpe", "mean_translation_m"}));
    r["mean_rpe_rotation_deg"] = number(at(m, {"rpe", "mean_rotation_deg"}));
    r["metrics"] = runs.first_out[i] + "/metrics.json";
    rows.push_back(r);
  }
  // Against PCL's FLANN (the first row): the ratio of medians and the widest range the runs
  // allow; no figure (null) where a time is missing or zero.
  for (std::size_t i = 0; i < rows.size(); ++i) {
    auto& r = rows[i];
    const bool have = !times[0].first.samples.empty() && !times[i].first.samples.empty();
    const bool have_e2e = !times[0].second.samples.empty() && !times[i].second.samples.empty();
    r["kdtree_speedup_vs_flann_range"] = have ? ratio_range(times[0].first, times[i].first) : ordered_json();
    r["end_to_end_reduction_vs_flann_percent_range"] =
        have_e2e ? reduction_range_percent(times[0].second, times[i].second) : ordered_json();
    r["kdtree_speedup_vs_flann"] = have ? r["kdtree_speedup_vs_flann_range"]["median"] : ordered_json();
    r["end_to_end_reduction_vs_flann_percent"] =
        have_e2e ? r["end_to_end_reduction_vs_flann_percent_range"]["median"] : ordered_json();
  }
  return rows;
}

// comparison.json: the rows, the machine, and the approximate search's errors against the exact one's.
ordered_json comparison_doc(const OdometryOptions& o, const Machine& machine,
                            const std::vector<std::pair<std::string, Spread>>& timed, const ordered_json& rows) {
  const auto diff = [&](const char* key) {
    const ordered_json &e = rows[1][key], &a = rows[2][key];
    return e.is_number() && a.is_number() ? ordered_json(a.get<double>() - e.get<double>()) : ordered_json();
  };
  ordered_json doc;
  doc["command"] = "odometry --compare";
  doc["command_line"] = o.command_line;
  doc["sequence"] = o.sequence;
  doc["repeat"] = o.repeat;
  doc["machine"] = to_json(machine);
  doc["warnings"] = baseline_warnings(machine, timed);
  doc["rows"] = rows;
  doc["approx_vs_exact"] = {{"t_err_percent_points", diff("t_err_percent")},
                            {"r_err_deg_per_m", diff("r_err_deg_per_m")},
                            {"ate_rmse_m", diff("ate_rmse_m")},
                            {"paper",
                             "DP4: approximate search leaves the translational error unchanged and adds "
                             "0.05 deg/m of rotational error"}};
  doc["notes"] = {
      "sums over every pair of the sequence; KD-tree time: the 3D KD-tree searches (tree builds stay on "
      "the CPU in every row, measured)",
      "accelerator: end to end = the run's CPU time without its KD-tree searches + the modeled search and "
      "host-transfer time + searches that could not be batched at their CPU time",
      "CPU energy is not modeled: the energy column is the accelerator's only",
      "CPU rows: the median of --repeat runs, interleaved with the other back-ends; *_spread gives min, "
      "max and every sample; a speed-up's range is base min / row max .. base max / row min",
      "each row is its own run: the CPU parts differ by measurement noise, and by the other work on the "
      "machine when pairs run side by side (--jobs)"};
  return doc;
}

// The table on stdout (the change in end-to-end time against FLANN, not its reduction), then the
// baseline's warnings on stderr.
void print_table(const OdometryOptions& o, const Machine& machine, const ordered_json& rows,
                 const std::vector<std::pair<Spread, Spread>>& times, const ordered_json& doc) {
  std::printf("tigris odometry --compare: %s, %s\n", o.sequence.c_str(), o.preset.c_str());
  std::printf("  %-32s %-22s %-18s %-22s %-20s %10s %8s %10s %8s\n", "back-end", "KD-tree s [min-max]", "KD x [range]",
              "end2end s [min-max]", "vs FLANN [range]", "KD energy", "t_err %", "r_err d/m", "ATE m");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const double e = r["kdtree_energy_pj"].is_null() ? NAN : r["kdtree_energy_pj"].get<double>() * 1e-6;
    const auto v = [&](const char* k) { return r[k].is_null() ? NAN : r[k].get<double>(); };
    const auto sp = [](const Spread& s, const char* fmt) {
      return s.samples.empty() ? std::string("-") : spread_cell(s, fmt);
    };
    const ordered_json& speedup = r["kdtree_speedup_vs_flann_range"];
    ordered_json vs = r["end_to_end_reduction_vs_flann_percent_range"];
    if (vs.is_object()) {  // printed as the change in time: a reduction is negative
      for (auto& [k, x] : vs.items())
        if (x.is_number()) x = -x.get<double>();
      std::swap(vs["min"], vs["max"]);
    }
    std::printf("  %-32s %-22s %-18s %-22s %-20s %10s %8s %10s %8s\n", r["label"].get<std::string>().c_str(),
                sp(times[i].first, "%.3g").c_str(),
                i == 0              ? "base"
                : speedup.is_null() ? "-"
                                    : (range_cell(speedup, "%.3g") + "x").c_str(),
                sp(times[i].second, "%.3g").c_str(),
                i == 0         ? "base"
                : vs.is_null() ? "-"
                               : (range_cell(vs, "%+.1f") + "%").c_str(),
                std::isfinite(e) ? (cell(e, "%.0f") + " uJ").c_str() : "n/a (CPU)",
                cell(v("t_err_percent"), "%.3f").c_str(), cell(v("r_err_deg_per_m"), "%.5f").c_str(),
                cell(v("ate_rmse_m"), "%.3f").c_str());
  }
  std::printf("  CPU rows: median [min-max] of %d runs, measured; accelerator: modeled, run once\n  machine: %s\n",
              o.repeat, machine_line(machine).c_str());
  const ordered_json& ave = doc["approx_vs_exact"];
  const double d_t = ave["t_err_percent_points"].is_null() ? NAN : ave["t_err_percent_points"].get<double>(),
               d_r = ave["r_err_deg_per_m"].is_null() ? NAN : ave["r_err_deg_per_m"].get<double>();
  std::printf(
      "  approximate against exact: translation %s points, rotation %s deg/m "
      "(the paper, DP4: unchanged, +0.05)\n",
      cell(d_t, "%+.3f").c_str(), cell(d_r, "%+.5f").c_str());
  std::printf("  wrote %s/comparison.json (runs in %s/{flann,exact,approx,accel}/%s)\n", o.out.c_str(), o.out.c_str(),
              o.repeat > 1 ? " and <back-end>-repeat-k/" : "");
  for (const auto& w : doc["warnings"])
    std::fprintf(stderr, "tigris odometry --compare: warning: %s\n", w.get<std::string>().c_str());
}

}  // namespace

int run_odometry_compare(const OdometryOptions& o) {
  if (o.argv.empty()) throw std::logic_error("--compare: the command's arguments were not kept");
  Machine machine = machine_before();
  const Runs runs = run_backends(o);
  machine_after(machine);
  std::vector<std::pair<std::string, Spread>> timed;
  std::vector<std::pair<Spread, Spread>> times;  // KD-tree, end to end; empty spread: no figure
  ordered_json rows = backend_rows(runs, times, timed);
  const ordered_json doc = comparison_doc(o, machine, timed, rows);
  // The accelerator run's metrics.json gets the CPU baseline beside its own figures.
  {
    const std::string path = o.out + "/accel/metrics.json";
    ordered_json m = parse_json_text(read_input(path, "the accelerator run's metrics", kMaxSettingsBytes), path);
    m["compared_with_cpu"] = {
        {"comparison", o.out + "/comparison.json"},
        {"flann_kdtree_seconds", rows[0]["kdtree_seconds"]},
        {"flann_end_to_end_seconds", rows[0]["end_to_end_seconds"]},
        {"exact_kdtree_seconds", rows[1]["kdtree_seconds"]},
        {"kdtree_speedup_vs_flann", rows[3]["kdtree_speedup_vs_flann"]},
        {"end_to_end_reduction_vs_flann_percent", rows[3]["end_to_end_reduction_vs_flann_percent"]},
        {"approx_vs_exact", doc["approx_vs_exact"]}};
    write_file(path,
               [&](std::ostream& f) { f << m.dump(2, ' ', false, ordered_json::error_handler_t::replace) << '\n'; });
  }
  write_file(o.out + "/comparison.json",
             [&](std::ostream& f) { f << doc.dump(2, ' ', false, ordered_json::error_handler_t::replace) << '\n'; });
  print_table(o, machine, rows, times, doc);
  return runs.worst;
}

}  // namespace tigris
