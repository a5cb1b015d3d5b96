// `tigris odometry --compare` (issue 20, "the accelerator over a sequence"): the same sequence
// registered with PCL's FLANN, the golden model's exact and approximate search on the CPU, and
// the accelerator model in the loop, each a `tigris odometry` of its own in OUT/<back-end>/
// (resumable, --jobs or --slurm as given), then one table: KD-tree time (measured on the CPU,
// modeled for the accelerator), end to end and its reduction against FLANN, KD-tree energy, and
// KITTI's errors, with the approximate search's accuracy against the exact one.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "children.hpp"
#include "sw_ref/json_file.hpp"
#include "odometry_command.hpp"
#include "report.hpp"

namespace tigris {
namespace {

using nlohmann::ordered_json;

struct Backend {
  const char* search;
  const char* label;
};
constexpr Backend kBackends[] = {{"flann", "CPU, PCL's FLANN"},
                                 {"exact", "CPU, golden model (exact)"},
                                 {"approx", "CPU, golden model (approximate)"},
                                 {"accel", "accelerator (exact), modeled"}};

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
    if (x.search != "approx") x.approx_thd.clear();
    if (x.search != "accel") {
      x.accel_config.clear();
      x.accel_sets.clear();
    }
    v.push_back(x);
  }
  return v;
}

int run_odometry_compare(const OdometryOptions& o) {
  if (o.argv.empty()) throw std::logic_error("--compare: the command's arguments were not kept");
  ordered_json rows = ordered_json::array();
  int worst = 0;
  for (const Backend& b : kBackends) {
    const std::string search = b.search, out = o.out + "/" + search;
    std::vector<std::string> drop{"--out", "--search", "--sequence", "--synthetic", "--seed"};
    if (search != "approx") drop.push_back("--approx-thd");
    if (search != "accel") drop.insert(drop.end(), {"--accel-config", "--accel-set"});
    std::fprintf(stderr, "tigris odometry --compare: %s (--search %s --out %s)\n", b.label, b.search, out.c_str());
    const int code = wait_child(start_child(
        rerun_args(o.argv, {"--compare"}, drop, {"--sequence", o.sequence, "--search", search, "--out", out})));
    if (code != 0 && code != 1)
      throw std::invalid_argument("--compare: the " + search + " run failed (exit " + std::to_string(code) +
                                  "; its message is above); a rerun resumes");
    worst = std::max(worst, code);
    const ordered_json m = parse_json_text(read_input(out + "/metrics.json", "a back-end's metrics", kMaxSettingsBytes),
                                           out + "/metrics.json");
    const bool accel = search == "accel";
    ordered_json r;
    r["back_end"] = search;
    r["label"] = b.label;
    r["kdtree_seconds"] = number(accel ? at(m, {"accelerator", "modeled_kdtree_seconds"}) : at(m, {"totals", "kdtree_search_seconds"}));
    r["end_to_end_seconds"] = number(accel ? at(m, {"accelerator", "modeled_end_to_end_seconds"}) : at(m, {"totals", "seconds"}));
    r["timing"] = accel ? "modeled (the accelerator's jobs; the rest measured on this CPU)" : "measured on this CPU";
    r["kdtree_energy_pj"] = accel ? number(at(m, {"accelerator", "kdtree_energy_pj"})) : ordered_json();
    r["not_converged_pairs"] = m.value("not_converged_pairs", 0);
    r["t_err_percent"] = number(at(m, {"kitti", "t_err_percent"}));
    r["r_err_deg_per_m"] = number(at(m, {"kitti", "r_err_deg_per_m"}));
    r["ate_rmse_m"] = number(at(m, {"ate", "rmse_m"}));
    r["mean_rpe_translation_m"] = number(at(m, {"rpe", "mean_translation_m"}));
    r["mean_rpe_rotation_deg"] = number(at(m, {"rpe", "mean_rotation_deg"}));
    r["metrics"] = out + "/metrics.json";
    rows.push_back(r);
  }
  // Against PCL's FLANN (the first row); no figure (null) where a time is missing or zero.
  const auto seconds = [](const ordered_json& r, const char* key) {
    const double x = r[key].is_number() ? r[key].get<double>() : NAN;
    return std::isfinite(x) && x > 0.0 ? x : NAN;
  };
  const double base_kd = seconds(rows[0], "kdtree_seconds"), base_e2e = seconds(rows[0], "end_to_end_seconds");
  for (auto& r : rows) {
    r["kdtree_speedup_vs_flann"] = number(base_kd / seconds(r, "kdtree_seconds"));
    r["end_to_end_reduction_vs_flann_percent"] = number(100.0 * (1.0 - seconds(r, "end_to_end_seconds") / base_e2e));
  }
  const auto diff = [&](const char* key) {
    const ordered_json &e = rows[1][key], &a = rows[2][key];
    return e.is_number() && a.is_number() ? ordered_json(a.get<double>() - e.get<double>()) : ordered_json();
  };
  ordered_json doc;
  doc["command"] = "odometry --compare";
  doc["command_line"] = o.command_line;
  doc["sequence"] = o.sequence;
  doc["rows"] = rows;
  doc["approx_vs_exact"] = {{"t_err_percent_points", diff("t_err_percent")},
                            {"r_err_deg_per_m", diff("r_err_deg_per_m")},
                            {"ate_rmse_m", diff("ate_rmse_m")},
                            {"paper", "DP4: approximate search leaves the translational error unchanged and adds 0.05 deg/m "
                                      "of rotational error"}};
  doc["notes"] = {"sums over every pair of the sequence; KD-tree time: the 3D KD-tree searches (tree builds stay on "
                  "the CPU in every row, measured)",
                  "accelerator: end to end = the run's CPU time without its KD-tree searches + the modeled search and "
                  "host-transfer time + searches that could not be batched at their CPU time",
                  "CPU energy is not modeled: the energy column is the accelerator's only",
                  "each row is its own run: the CPU parts differ by measurement noise, and by the other work on the "
                  "machine when pairs run side by side (--jobs)"};
  // The accelerator run's metrics.json gets the CPU baseline beside its own figures.
  {
    const std::string path = o.out + "/accel/metrics.json";
    ordered_json m = parse_json_text(read_input(path, "the accelerator run's metrics", kMaxSettingsBytes), path);
    m["compared_with_cpu"] = {{"comparison", o.out + "/comparison.json"},
                              {"flann_kdtree_seconds", rows[0]["kdtree_seconds"]},
                              {"flann_end_to_end_seconds", rows[0]["end_to_end_seconds"]},
                              {"exact_kdtree_seconds", rows[1]["kdtree_seconds"]},
                              {"kdtree_speedup_vs_flann", rows[3]["kdtree_speedup_vs_flann"]},
                              {"end_to_end_reduction_vs_flann_percent", rows[3]["end_to_end_reduction_vs_flann_percent"]},
                              {"approx_vs_exact", doc["approx_vs_exact"]}};
    write_file(path, [&](std::ostream& f) { f << m.dump(2, ' ', false, ordered_json::error_handler_t::replace) << '\n'; });
  }
  write_file(o.out + "/comparison.json",
             [&](std::ostream& f) { f << doc.dump(2, ' ', false, ordered_json::error_handler_t::replace) << '\n'; });

  std::printf("tigris odometry --compare: %s, %s\n", o.sequence.c_str(), o.preset.c_str());
  std::printf("  %-32s %10s %8s %11s %9s %10s %8s %10s %8s\n", "back-end", "KD-tree s", "KD x", "end2end s", "vs FLANN",
              "KD energy", "t_err %", "r_err d/m", "ATE m");
  for (const auto& r : rows) {
    const double e = r["kdtree_energy_pj"].is_null() ? NAN : r["kdtree_energy_pj"].get<double>() * 1e-6;
    const auto v = [&](const char* k) { return r[k].is_null() ? NAN : r[k].get<double>(); };
    std::printf("  %-32s %10s %8s %11s %8s%% %10s %8s %10s %8s\n", r["label"].get<std::string>().c_str(),
                cell(v("kdtree_seconds"), "%.2f").c_str(), cell(v("kdtree_speedup_vs_flann"), "%.1f").c_str(),
                cell(v("end_to_end_seconds"), "%.1f").c_str(), cell(v("end_to_end_reduction_vs_flann_percent"), "%.1f").c_str(),
                std::isfinite(e) ? (cell(e, "%.0f") + " uJ").c_str() : "n/a (CPU)", cell(v("t_err_percent"), "%.3f").c_str(),
                cell(v("r_err_deg_per_m"), "%.5f").c_str(), cell(v("ate_rmse_m"), "%.3f").c_str());
  }
  std::printf("  approximate against exact: translation %s points, rotation %s deg/m (the paper, DP4: unchanged, +0.05)\n",
              cell(doc["approx_vs_exact"]["t_err_percent_points"].is_null() ? NAN : doc["approx_vs_exact"]["t_err_percent_points"].get<double>(), "%+.3f").c_str(),
              cell(doc["approx_vs_exact"]["r_err_deg_per_m"].is_null() ? NAN : doc["approx_vs_exact"]["r_err_deg_per_m"].get<double>(), "%+.5f").c_str());
  std::printf("  wrote %s/comparison.json (runs in %s/{flann,exact,approx,accel}/)\n", o.out.c_str(), o.out.c_str());
  return worst;
}

}  // namespace tigris
