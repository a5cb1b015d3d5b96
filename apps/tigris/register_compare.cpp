// `tigris register --compare` ("side by side"): the registration on four back-ends,
// each run by this program in a child process (fair timing: no heap or cache left over from
// another back-end), then one table from their registration.json files. The CPU back-ends are
// timed --repeat times, interleaved with the others so a slow minute of the machine touches
// every back-end alike; the table gives their medians with min and max (cpu_baseline.hpp).
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

#include "core/children.hpp"
#include "register_command.hpp"
#include "registration/report.hpp"
#include "registration/search_backends.hpp"
#include "testbench/cpu_baseline.hpp"
#include "testbench/report.hpp"
#include "testbench/run_inputs.hpp"

namespace tigris {
namespace {

using nlohmann::ordered_json;

using Variant = registration::SearchBackend;
// The back-ends compared, in the table's order (registration/search_backends.hpp).
const std::vector<Variant> kVariants = {registration::search_backend("flann"), registration::search_backend("exact"),
                                        registration::search_backend("accel"),
                                        registration::search_backend("accel-approx")};

// Repeat 1 in OUT/<back-end>/ (the layout of one run), repeat k in OUT/<back-end>-repeat-k/.
std::string run_dir(const std::string& out, const Variant& v, int k) {
  return out + "/" + v.search + (k == 1 ? std::string() : "-repeat-" + std::to_string(k));
}

// The command's arguments for one back-end: --compare and --out dropped, --approx-thd kept for
// the approximate run only, --accel-config and --accel-set for the accelerator runs only, then
// --search and --out of the variant.
std::vector<std::string> variant_args(const std::vector<std::string>& argv, const Variant& v, const std::string& out) {
  std::vector<std::string> drop{"--out", "--repeat"};
  if (!v.approximate) drop.push_back("--approx-thd");
  if (!v.in_loop()) drop.insert(drop.end(), {"--accel-config", "--accel-set"});
  return rerun_args(argv, {"--compare"}, drop, {"--search", v.search, "--out", out});
}

double search_seconds(const registration::Report& reg) {
  double s = 0.0;
  for (const registration::StageReport& st : reg.result.stages) s += st.kdtree.search_seconds;
  return s;
}

// The CPU back-ends are deterministic: runs that register differently are a bug, not noise.
bool same_transform(const registration::Report& a, const registration::Report& b) {
  return a.degenerate() == b.degenerate() && (a.degenerate() || a.result.transform == b.result.transform);
}

}  // namespace

namespace {

// The flags that do not go with --compare, then every back-end's flags, each checked by the
// command itself (--check-flags) before the first one runs and before the folder is claimed.
void check_compare_flags(const CLI::App& app, const RegisterOptions& o) {
  for (const char* flag : {"--search", "--record-trace", "--list-config", "--inject-kth", "--inject-shell"})
    if (app.count(flag))
      throw std::invalid_argument(std::string(flag) + " does not go with --compare (it runs the paper's back-ends " +
                                  "flann, exact, accel and accel-approx without error injection)");
  if (o.argv.empty()) throw std::logic_error("--compare: the command's arguments were not kept");
  for (const Variant& v : kVariants) {
    std::vector<std::string> args = variant_args(o.argv, v, o.out + "/" + v.search);
    args.push_back("--check-flags");
    if (wait_child(start_child(args)) != 0)
      throw std::invalid_argument(std::string("--compare: the flags do not hold for the ") + v.search +
                                  " back-end (its message is above); nothing was run");
  }
}

}  // namespace

namespace {

// Every back-end's registration.json, repeat by repeat, and the worst exit code (0, or 1: a
// back-end did not converge).
struct VariantRuns {
  std::vector<std::vector<registration::Report>> regs =
      std::vector<std::vector<registration::Report>>(kVariants.size());
  ordered_json paths = ordered_json::object();  // comparison.json's "runs"
  int worst = 0;
};

// The back-ends in child processes: the CPU ones --repeat times, interleaved with the others.
VariantRuns run_variants(const RegisterOptions& o) {
  VariantRuns runs;
  for (int k = 1; k <= o.repeat; ++k)
    for (std::size_t i = 0; i < kVariants.size(); ++i) {
      const Variant& v = kVariants[i];
      if (k > 1 && !v.cpu) continue;
      const std::string out = run_dir(o.out, v, k);
      std::fprintf(
          stderr, "tigris register --compare: %s%s (--search %s --out %s)\n", v.label,
          v.cpu && o.repeat > 1 ? (", run " + std::to_string(k) + " of " + std::to_string(o.repeat)).c_str() : "",
          v.search, out.c_str());
      const int code = wait_child(start_child(variant_args(o.argv, v, out)));
      if (code != 0 && code != 1)
        throw std::invalid_argument(std::string("--compare: the ") + v.search + " registration failed (exit " +
                                    std::to_string(code) + "; its message is above)");
      runs.worst = std::max(runs.worst, code);
      const std::string path = out + "/registration.json";
      std::vector<registration::Report>& regs = runs.regs[i];
      regs.push_back(registration::read_report(path));
      runs.paths[v.search].push_back(path);
      if (!same_transform(regs.back(), regs.front()))
        throw std::runtime_error(std::string("--compare: the ") + v.search + " back-end's run " + std::to_string(k) +
                                 " found another transform than its run 1 (" + path +
                                 "): the registration is not deterministic");
    }
  return runs;
}

// The table: a row a back-end, with the spreads of its KD-tree and end-to-end times.
struct Table {
  ordered_json rows = ordered_json::array();
  std::vector<std::pair<Spread, Spread>> times;       // KD-tree, end to end of each row
  std::vector<std::pair<std::string, Spread>> timed;  // the CPU rows' KD-tree times, for the warnings
};

ordered_json variant_row(const Variant& v, const std::vector<registration::Report>& regs,
                         const std::pair<Spread, Spread>& times) {
  const registration::Report& reg = regs.front();
  const bool accel = reg.in_loop();
  ordered_json row;
  row["back_end"] = v.search;
  row["label"] = v.label;
  row["status"] = reg.result.status;
  row["runs"] = regs.size();
  row["kdtree_seconds"] = times.first.median;
  row["end_to_end_seconds"] = times.second.median;
  row["kdtree_seconds_spread"] = to_json(times.first);
  row["end_to_end_seconds_spread"] = to_json(times.second);
  row["timing"] = accel ? "modeled (the accelerator's jobs; the rest measured on this CPU, once)"
                        : "measured on this CPU: the median of the runs";
  row["kdtree_energy_pj"] = accel ? ordered_json(registration::loop_figures(reg.result).energy_pj) : ordered_json();
  double build = 0.0;
  for (const registration::StageReport& st : reg.result.stages) build += st.kdtree.build_seconds;
  row["tree_build_seconds"] = build;
  const auto err = reg.error();
  row["error"] =
      err ? ordered_json{{"translation_m", err->translation_m}, {"rotation_deg", err->rotation_deg}} : ordered_json();
  row["transform"] = registration::transform_json(reg);
  return row;
}

Table comparison_table(const VariantRuns& runs) {
  Table t;
  for (std::size_t i = 0; i < kVariants.size(); ++i) {
    const Variant& v = kVariants[i];
    const bool accel = runs.regs[i].front().in_loop();
    std::vector<double> kd, e2e;
    for (const registration::Report& r : runs.regs[i]) {
      const registration::LoopFigures l = registration::loop_figures(r.result);
      kd.push_back(accel ? l.modeled_kd : search_seconds(r));
      e2e.push_back(accel ? l.modeled_e2e : r.result.total_seconds);
    }
    t.times.emplace_back(spread_of(kd), spread_of(e2e));
    if (v.cpu) t.timed.emplace_back(std::string(v.search) + "'s KD-tree time", t.times.back().first);
    t.rows.push_back(variant_row(v, runs.regs[i], t.times.back()));
  }
  // Against the CPU baseline, PCL's FLANN (the first row): the ratio of medians, and the widest
  // range the runs allow.
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    auto& row = t.rows[i];
    row["kdtree_speedup_vs_flann_range"] = ratio_range(t.times[0].first, t.times[i].first);
    row["end_to_end_reduction_vs_flann_percent_range"] = reduction_range_percent(t.times[0].second, t.times[i].second);
    row["kdtree_speedup_vs_flann"] = row["kdtree_speedup_vs_flann_range"]["median"];
    row["end_to_end_reduction_vs_flann_percent"] = row["end_to_end_reduction_vs_flann_percent_range"]["median"];
  }
  return t;
}

ordered_json comparison_doc(const RegisterOptions& o, const Machine& machine, const std::vector<std::string>& warnings,
                            const Table& t, const VariantRuns& runs) {
  ordered_json doc;
  doc["command"] = "register --compare";
  doc["command_line"] = o.command_line;
  doc["repeat"] = o.repeat;
  doc["machine"] = to_json(machine);
  doc["warnings"] = warnings;
  doc["rows"] = t.rows;
  doc["runs"] = runs.paths;
  doc["notes"] = {"KD-tree time: the 3D KD-tree searches (tree builds stay on the CPU in every row, measured)",
                  "CPU rows: the median of --repeat runs, interleaved with the other back-ends; *_spread gives "
                  "min, max and every sample; a speed-up's range is base min / row max .. base max / row min",
                  "accelerator rows: end to end = the run's CPU time without its KD-tree searches + the modeled "
                  "search and host-transfer time + searches that could not be batched at their CPU time; run once "
                  "(the modeled part is deterministic)",
                  "CPU energy is not modeled: the energy column is the accelerator's only"};
  return doc;
}

void print_table(const RegisterOptions& o, const Machine& machine, const Table& t) {
  std::printf("tigris register --compare: preset %s, %s\n", o.preset.c_str(),
              o.source.empty() ? "the built-in synthetic pair" : (o.source + " -> " + o.target).c_str());
  std::printf("  %-26s %-24s %-18s %-24s %-22s %11s %9s %9s\n", "back-end", "KD-tree s [min-max]", "KD x [range]",
              "end to end s [min-max]", "vs FLANN [range]", "KD energy", "error m", "error deg");
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const auto& row = t.rows[i];
    char energy[32] = "n/a (CPU)", err_m[32] = "-", err_deg[32] = "-";
    if (!row["kdtree_energy_pj"].is_null())
      std::snprintf(energy, sizeof energy, "%.1f uJ", row["kdtree_energy_pj"].get<double>() * 1e-6);
    if (!row["error"].is_null()) {
      std::snprintf(err_m, sizeof err_m, "%.4f", row["error"]["translation_m"].get<double>());
      std::snprintf(err_deg, sizeof err_deg, "%.4f", row["error"]["rotation_deg"].get<double>());
    }
    ordered_json vs = row["end_to_end_reduction_vs_flann_percent_range"];
    for (auto& [k, x] : vs.items())  // printed as the change in time: a reduction is negative
      if (x.is_number()) x = -x.get<double>();
    std::swap(vs["min"], vs["max"]);
    std::printf("  %-26s %-24s %-18s %-24s %-22s %11s %9s %9s%s\n", row["label"].get<std::string>().c_str(),
                spread_cell(t.times[i].first, "%.4f").c_str(),
                i == 0 ? "base" : (range_cell(row["kdtree_speedup_vs_flann_range"], "%.3g") + "x").c_str(),
                spread_cell(t.times[i].second, "%.3f").c_str(),
                i == 0 ? "base" : (range_cell(vs, "%+.1f") + "%").c_str(), energy, err_m, err_deg,
                row["status"] == "converged" ? "" : "  (not converged)");
  }
  std::printf(
      "  KD-tree: searches only (tree builds stay on the CPU); CPU rows: median [min-max] of %d runs, measured;\n"
      "  accelerator rows: modeled, run once; CPU energy is not modeled.\n"
      "  machine: %s\n  Table: %s/comparison.json\n",
      o.repeat, machine_line(machine).c_str(), o.out.c_str());
}

}  // namespace

int run_register_compare(const CLI::App& app, const RegisterOptions& o) {
  check_compare_flags(app, o);
  if (o.check_flags) return 0;  // a check only: the folder is not claimed, nothing written or removed
  std::vector<std::string> outputs{"comparison.json"};
  for (const Variant& v : kVariants) {
    outputs.push_back(std::string(v.search) + "/");
    if (v.cpu) outputs.push_back(std::string(v.search) + "-repeat-*/");
  }
  OutFolder folder(o.out, {"register", {}, nlohmann::json::object(), register_inputs(o), outputs, false, {}});
  Machine machine = machine_before();
  const VariantRuns runs = run_variants(o);
  machine_after(machine);
  const Table t = comparison_table(runs);
  const std::vector<std::string> warnings = baseline_warnings(machine, t.timed);
  const ordered_json doc = comparison_doc(o, machine, warnings, t, runs);
  // Every back-end read the inputs digested here at the start (each child digests them again).
  folder.check_inputs();
  write_file(o.out + "/comparison.json",
             [&](std::ostream& f) { f << doc.dump(2, ' ', false, ordered_json::error_handler_t::replace) << '\n'; });
  print_table(o, machine, t);
  for (const std::string& w : warnings) std::fprintf(stderr, "tigris register --compare: warning: %s\n", w.c_str());
  folder.finish();
  return runs.worst;
}

}  // namespace tigris
