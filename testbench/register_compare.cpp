// `tigris register --compare` (issue 19, "side by side"): the registration on four back-ends,
// each run by this program in a child process (fair timing: no heap or cache left over from
// another back-end), then one table from their registration.json files.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "children.hpp"
#include "run_inputs.hpp"
#include "sw_ref/json_file.hpp"
#include "register_command.hpp"
#include "report.hpp"

namespace tigris {
namespace {

using nlohmann::ordered_json;

struct Variant {
  const char* search;  // --search
  const char* label;   // in the table
};
constexpr Variant kVariants[] = {{"flann", "CPU, PCL's FLANN"},
                                 {"exact", "CPU, golden model (exact)"},
                                 {"accel", "accelerator, exact"},
                                 {"accel-approx", "accelerator, approximate"}};

// The command's arguments for one back-end: --compare and --out dropped, --approx-thd kept for
// the approximate run only, --accel-config and --accel-set for the accelerator runs only, then
// --search and --out of the variant.
std::vector<std::string> variant_args(const std::vector<std::string>& argv, const Variant& v, const std::string& out) {
  const std::string search = v.search;
  std::vector<std::string> drop{"--out"};
  if (search != "accel-approx") drop.push_back("--approx-thd");
  if (search.rfind("accel", 0) != 0) drop.insert(drop.end(), {"--accel-config", "--accel-set"});
  return rerun_args(argv, {"--compare"}, drop, {"--search", v.search, "--out", out});
}

double search_seconds(const ordered_json& reg) {
  double s = 0.0;
  for (const auto& [name, st] : reg["stages"].items()) s += st.value("search_seconds", 0.0);
  return s;
}

}  // namespace

int run_register_compare(const CLI::App& app, const RegisterOptions& o) {
  for (const char* flag : {"--search", "--record-trace", "--list-config", "--inject-kth", "--inject-shell"})
    if (app.count(flag))
      throw std::invalid_argument(std::string(flag) + " does not go with --compare (it runs the paper's back-ends " +
                                  "flann, exact, accel and accel-approx without error injection)");
  if (o.argv.empty()) throw std::logic_error("--compare: the command's arguments were not kept");
  // Every back-end's flags are checked before the first one runs (and before the folder).
  for (const Variant& v : kVariants) {
    std::vector<std::string> args = variant_args(o.argv, v, o.out + "/" + v.search);
    args.push_back("--check-flags");
    if (wait_child(start_child(args)) != 0)
      throw std::invalid_argument(std::string("--compare: the flags do not hold for the ") + v.search +
                                  " back-end (its message is above); nothing was run");
  }
  nlohmann::json inputs = nlohmann::json::array();
  for (const auto& [role, path] : {std::pair<const char*, std::string>{"source", o.source}, {"target", o.target},
                                  {"config", o.config}, {"ground truth", o.ground_truth},
                                  {"KITTI poses", o.kitti_poses}, {"accelerator config", o.accel_config}})
    if (!path.empty()) inputs.push_back(input_file(role, path));
  std::vector<std::string> outputs{"comparison.json"};
  for (const Variant& v : kVariants) outputs.push_back(std::string(v.search) + "/");
  OutFolder folder(o.out, {"register", {}, nlohmann::json::object(), inputs, outputs, false, {}});
  ordered_json rows = ordered_json::array();
  ordered_json runs = ordered_json::object();
  const std::string flann_out = o.out + "/flann";
  int worst = 0;
  for (const Variant& v : kVariants) {
    const std::string out = o.out + "/" + v.search;
    std::fprintf(stderr, "tigris register --compare: %s (--search %s --out %s)\n", v.label, v.search, out.c_str());
    const int code = wait_child(start_child(variant_args(o.argv, v, out)));
    if (code != 0 && code != 1)
      throw std::invalid_argument(std::string("--compare: the ") + v.search + " registration failed (exit " +
                                  std::to_string(code) + "; its message is above)");
    worst = std::max(worst, code);
    const std::string path = out + "/registration.json";
    const ordered_json reg = parse_json_text(read_input(path, "the back-end's report", kMaxSettingsBytes), path);
    ordered_json row;
    row["back_end"] = v.search;
    row["label"] = v.label;
    row["status"] = reg["status"];
    const bool accel = reg.contains("accelerator");
    row["kdtree_seconds"] = accel ? reg["accelerator"]["modeled_kdtree_seconds"].get<double>() : search_seconds(reg);
    row["end_to_end_seconds"] = accel ? reg["accelerator"]["modeled_end_to_end_seconds"].get<double>()
                                      : reg["seconds"].get<double>();
    row["timing"] = accel ? "modeled (the accelerator's jobs; the rest measured on this CPU)" : "measured on this CPU";
    row["kdtree_energy_pj"] = accel ? reg["accelerator"]["kdtree_energy_pj"] : ordered_json();
    row["tree_build_seconds"] = 0.0;
    for (const auto& [name, st] : reg["stages"].items()) row["tree_build_seconds"] = row["tree_build_seconds"].get<double>() + st.value("build_seconds", 0.0);
    row["error"] = reg.contains("error") ? ordered_json{{"translation_m", reg["error"]["translation_m"]},
                                                        {"rotation_deg", reg["error"]["rotation_deg"]}}
                                         : ordered_json();
    row["transform"] = reg["transform"];
    rows.push_back(row);
    runs[v.search] = out + "/registration.json";
  }
  // Against the CPU baseline, PCL's FLANN (the first row).
  const double base_kd = rows[0]["kdtree_seconds"].get<double>(), base_e2e = rows[0]["end_to_end_seconds"].get<double>();
  for (auto& row : rows) {
    row["kdtree_speedup_vs_flann"] = base_kd / std::max(1e-12, row["kdtree_seconds"].get<double>());
    row["end_to_end_reduction_vs_flann_percent"] = 100.0 * (1.0 - row["end_to_end_seconds"].get<double>() / base_e2e);
  }
  ordered_json doc;
  doc["command"] = "register --compare";
  doc["command_line"] = o.command_line;
  doc["rows"] = rows;
  doc["runs"] = runs;
  doc["notes"] = {"KD-tree time: the 3D KD-tree searches (tree builds stay on the CPU in every row, measured)",
                  "accelerator rows: end to end = the run's CPU time without its KD-tree searches + the modeled "
                  "search and host-transfer time + searches that could not be batched at their CPU time",
                  "CPU energy is not modeled: the energy column is the accelerator's only",
                  "each row is its own run; the CPU parts of the rows differ by measurement noise"};
  write_file(o.out + "/comparison.json",
             [&](std::ostream& f) { f << doc.dump(2, ' ', false, ordered_json::error_handler_t::replace) << '\n'; });

  std::printf("tigris register --compare: preset %s, %s\n", o.preset.c_str(),
              o.source.empty() ? "the built-in synthetic pair" : (o.source + " -> " + o.target).c_str());
  std::printf("  %-26s %11s %8s %12s %8s %11s %12s %10s\n", "back-end", "KD-tree s", "KD x", "end to end s", "vs FLANN",
              "KD energy", "error m", "error deg");
  for (const auto& row : rows) {
    char energy[32] = "n/a (CPU)", err_m[32] = "-", err_deg[32] = "-";
    if (!row["kdtree_energy_pj"].is_null())
      std::snprintf(energy, sizeof energy, "%.1f uJ", row["kdtree_energy_pj"].get<double>() * 1e-6);
    if (!row["error"].is_null()) {
      std::snprintf(err_m, sizeof err_m, "%.4f", row["error"]["translation_m"].get<double>());
      std::snprintf(err_deg, sizeof err_deg, "%.4f", row["error"]["rotation_deg"].get<double>());
    }
    char vs[16] = "base";
    if (&row != &rows[0]) std::snprintf(vs, sizeof vs, "%+.1f%%", -row["end_to_end_reduction_vs_flann_percent"].get<double>());
    std::printf("  %-26s %11.4f %7.1fx %12.4f %8s %11s %12s %10s%s\n", row["label"].get<std::string>().c_str(),
                row["kdtree_seconds"].get<double>(), row["kdtree_speedup_vs_flann"].get<double>(),
                row["end_to_end_seconds"].get<double>(), vs,
                energy, err_m, err_deg, row["status"] == "converged" ? "" : "  (not converged)");
  }
  std::printf("  KD-tree: searches only (tree builds stay on the CPU); accelerator rows modeled, CPU rows measured;\n"
              "  CPU energy is not modeled. Table: %s/comparison.json\n", o.out.c_str());
  folder.finish();
  return worst;
}

}  // namespace tigris
