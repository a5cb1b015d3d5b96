#include "report.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "core/input_file.hpp"
#include "core/json_file.hpp"
#include "core/visible_text.hpp"
#include "sw_ref/search.hpp"

namespace tigris::registration {

using nlohmann::ordered_json;

std::optional<PoseError> Report::error() const {
  if (!truth || degenerate()) return std::nullopt;
  return pose_error(truth->transform, result.transform);
}

std::optional<PoseError> Report::initial_error() const {
  if (!truth || degenerate()) return std::nullopt;
  return pose_error(truth->transform, result.initial);
}

double Report::kdtree_seconds() const {
  double kd = 0.0;
  for (const StageReport& s : result.stages) kd += s.kdtree.search_seconds + s.kdtree.build_seconds;
  return kd;
}

std::uint64_t Report::sampled_jobs() const {
  std::uint64_t n = 0;
  if (accelerator)
    for (const auto& j : accelerator->job_list) n += j.value("sampled", false);
  return n;
}

double modeled_kdtree_seconds(const SearchCounters& k) {
  return k.accel.modeled_search_seconds + k.accel.modeled_host_seconds + k.accel.fallback_seconds;
}

double modeled_stage_seconds(const StageReport& s) {
  return s.seconds - s.kdtree.search_seconds + modeled_kdtree_seconds(s.kdtree);
}

LoopFigures loop_figures(const RegistrationResult& r) {
  LoopFigures f;
  f.modeled_e2e = r.total_seconds;
  for (const StageReport& s : r.stages) {
    f.modeled_e2e += modeled_kdtree_seconds(s.kdtree) - s.kdtree.search_seconds;
    f.modeled_kd += modeled_kdtree_seconds(s.kdtree);
    f.energy_pj += s.kdtree.accel.energy_pj;
    f.jobs += s.kdtree.accel.jobs;
    f.fallback_searches += s.kdtree.accel.fallback_searches;
  }
  return f;
}

Report::Injection injection_of(const PipelineConfig& config) {
  return {config.inject.rpce_kth, config.inject.normals_shell_inner, config.inject.normals_shell_outer,
          config.normals.radius};
}

ordered_json job_row(std::uint64_t n, const AccelJob& job, const nlohmann::json& rep, const std::string& stage) {
  const nlohmann::json sampling = rep.value("sampling", nlohmann::json::object());
  ordered_json j;
  j["job"] = n;
  j["stage"] = stage;
  j["mode"] = to_string(job.params.mode);
  j["k"] = job.params.effective_k();
  j["radius"] = job.params.radius;
  j["approximate"] = job.params.approximate;
  j["queries"] = job.queries->size();
  j["points"] = job.points->size();
  j["verdict"] = rep.value("verdict", "");
  j["cycles"] = rep.value("cycles", 0);
  j["cycles_ci95"] = rep.value("cycles_ci95", nlohmann::json());  // [cycles, cycles] unless sampled
  j["sampled"] = sampling.value("sampled", false);
  j["simulated_queries"] = sampling.value("simulated", 0);
  j["modeled_seconds"] = rep.value("modeled_seconds", nlohmann::json());
  j["energy_pj"] = rep.value("energy_pj", 0.0);
  return j;
}

ordered_json matrix_json(const Eigen::Matrix4d& t) {
  ordered_json rows = ordered_json::array();
  for (int r = 0; r < 4; ++r) {
    ordered_json row = ordered_json::array();
    for (int c = 0; c < 4; ++c) row.push_back(t(r, c));
    rows.push_back(row);
  }
  return rows;
}

ordered_json transform_json(const Report& r) {
  return r.degenerate() ? ordered_json() : matrix_json(r.result.transform);
}

// ---- writing ----

namespace {

ordered_json stage_json(const StageReport& s, bool in_loop) {
  ordered_json j;
  j["seconds"] = s.seconds;
  const SearchCounters& k = s.kdtree;
  if (!s.search.empty()) {
    j["search"] = s.search;
    // PCL's batch calls loop over single points: each search is one query point.
    j["searches"] = k.searches;
    j["queries"] = k.searches;
    j["neighbors"] = k.neighbors;
    j["trees_built"] = k.builds;
    j["build_seconds"] = k.build_seconds;
    j["search_seconds"] = k.search_seconds;
    if (s.search != "flann") j["visits"] = visits_json<ordered_json>(k.visits);
    if (s.search == "approx" && !in_loop)
      j["leaders"] = {{"leaders", k.leaders.leaders},
                      {"followers", k.leaders.followers},
                      {"leader_buffer_full", k.leaders.leader_buffer_full}};
    if (in_loop) {
      // search_seconds above holds the jobs' simulation: the stage's figures on the hardware are these.
      const auto& a = k.accel;
      j["visits_note"] = "visits: the golden model's, of the fallback searches only";
      j["accelerator"] = {{"jobs", a.jobs},
                          {"queries", a.queries},
                          {"fallback_searches", a.fallback_searches},
                          {"fallback_cpu_seconds", a.fallback_seconds},
                          {"cycles", a.cycles},
                          {"modeled_search_seconds", a.modeled_search_seconds},
                          {"modeled_host_seconds", a.modeled_host_seconds},
                          {"modeled_kdtree_seconds", modeled_kdtree_seconds(k)},
                          {"modeled_stage_seconds", modeled_stage_seconds(s)},
                          {"energy_pj", a.energy_pj},
                          {"visits", visits_json<ordered_json>(a.visits)}};
    }
  } else {
    j["search"] = "none";
    j["searches"] = 0;
    j["queries"] = 0;
    j["search_seconds"] = 0.0;
  }
  for (const auto& [key, v] : s.info.items()) j[key] = v;
  return j;
}

ordered_json accelerator_json(const Report& r) {
  const LoopFigures f = loop_figures(r.result);
  return {{"jobs", f.jobs},
          {"sampled_jobs", r.sampled_jobs()},  // their cycles and energy estimated (docs/sampling.md)
          {"sampling", r.accelerator->sampling},
          {"fallback_searches", f.fallback_searches},
          {"modeled_kdtree_seconds", f.modeled_kd},
          {"kdtree_energy_pj", f.energy_pj},
          {"modeled_end_to_end_seconds", f.modeled_e2e},
          {"wall_seconds", r.result.total_seconds},
          {"how",
           "modeled end to end = the stages' CPU time without their KD-tree searches + the accelerator's "
           "modeled search and host-transfer time + the CPU time of the searches it could not batch (golden "
           "model); tree builds stay on the CPU; wall_seconds includes simulating the jobs"},
          {"every_job", "checked against the golden model, bit for bit"},
          {"config", r.accelerator->config},
          {"job_list", r.accelerator->job_list}};
}

ordered_json error_json(const PoseError& err, const PoseError& initial) {
  return {{"translation_m", err.translation_m},
          {"rotation_deg", err.rotation_deg},
          {"travelled_m", err.travelled_m},
          {"translation_m_per_m", err.translation_per_m},
          {"rotation_deg_per_m", err.rotation_deg_per_m},
          {"initial_translation_m", initial.translation_m},
          {"initial_rotation_deg", initial.rotation_deg}};
}

}  // namespace

ordered_json to_json(const Report& r) {
  const RegistrationResult& res = r.result;
  ordered_json doc;
  doc["command"] = "register";
  doc["version"] = Report::kVersion;
  doc["source"] = {{"name", r.source.name}, {"points", r.source.points}};
  doc["target"] = {{"name", r.target.name}, {"points", r.target.points}};
  doc["preset"] = r.preset;
  doc["search"] = r.search;
  // The injected error (also in config.inject): null when none.
  doc["injection"] = {{"rpce_kth", r.injection.rpce_kth},
                      {"normals_shell", r.injection.shell_outer > 0
                                            ? ordered_json::array({r.injection.shell_inner, r.injection.shell_outer})
                                            : ordered_json()},
                      {"normals_radius", r.injection.normals_radius}};
  doc["status"] = res.status;
  if (!res.problem.empty()) doc["problem"] = res.problem;
  doc["transform"] = transform_json(r);
  doc["initial_transform"] = matrix_json(res.initial);
  doc["seconds"] = res.total_seconds;
  ordered_json stages = ordered_json::object();
  for (const StageReport& s : res.stages) stages[s.name] = stage_json(s, r.in_loop());
  doc["stages"] = stages;
  const double kd = r.kdtree_seconds();
  doc["kdtree_seconds"] = kd;
  doc["kdtree_work"] = {{"distances_and_neighbors", r.work_spent}, {"max_work", r.max_work}};
  doc["kdtree_share"] = res.total_seconds > 0 ? kd / res.total_seconds : 0.0;
  if (r.in_loop()) doc["accelerator"] = accelerator_json(r);
  if (const auto err = r.error()) {
    doc["ground_truth"] = {{"source", r.truth->source}, {"transform", matrix_json(r.truth->transform)}};
    if (!r.truth->warning.empty()) doc["ground_truth"]["warning"] = r.truth->warning;
    doc["error"] = error_json(*err, *r.initial_error());
  }
  doc["config"] = ordered_json::parse(r.config.dump());
  if (!r.trace.is_null()) doc["trace"] = r.trace;
  return doc;
}

// ---- reading ----

namespace {

// Reads one document; every error names the source and the key.
// A count: a whole number at least 0 (a parsed file gives it unsigned, a document built here signed).
bool is_count(const ordered_json& x) {
  return x.is_number_unsigned() || (x.is_number_integer() && x.get<std::int64_t>() >= 0);
}

class Reader {
 public:
  explicit Reader(const std::string& source) : source_(source) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument(source_ + ": " + what + "; not a whole tigris register report");
  }
  void need(bool ok, const std::string& what) const {
    if (!ok) fail(what);
  }
  // `where` prefixes the key in messages ("stage 'icp': ").
  double number(const ordered_json& j, const char* key, const std::string& where = "") const {
    if (!j.contains(key)) return 0.0;
    const ordered_json& x = j[key];
    need(x.is_number() && x.get<double>() >= 0, where + "'" + key + "' is not a number at least 0");
    return x.get<double>();
  }
  std::uint64_t count(const ordered_json& j, const char* key, const std::string& where = "") const {
    if (!j.contains(key)) return 0;
    need(is_count(j[key]), where + "'" + key + "' is not a count (a whole number at least 0)");
    return j[key].get<std::uint64_t>();
  }
  std::string text(const ordered_json& j, const char* key, const std::string& where = "") const {
    if (!j.contains(key)) return {};
    need(j[key].is_string(), where + "'" + key + "' is not a text");
    return j[key].get<std::string>();
  }
  const ordered_json& object(const ordered_json& j, const char* key, const std::string& where = "") const {
    static const ordered_json kEmpty = ordered_json::object();
    if (!j.contains(key) || j[key].is_null()) return kEmpty;
    need(j[key].is_object(), where + "'" + key + "' is not an object");
    return j[key];
  }
  // A 4x4 matrix; `finite`: every entry a number (else a null entry reads as NaN, as NaN is written).
  Eigen::Matrix4d matrix(const ordered_json& m, const std::string& name, bool finite) const {
    bool ok = m.is_array() && m.size() == 4;
    for (std::size_t r = 0; ok && r < 4; ++r)
      ok = m[r].is_array() && m[r].size() == 4 && std::all_of(m[r].begin(), m[r].end(), [&](const ordered_json& x) {
             return finite ? x.is_number() && std::isfinite(x.get<double>()) : x.is_number() || x.is_null();
           });
    need(ok, "'" + name + "' is not a 4x4 matrix of " + (finite ? "finite numbers" : "numbers"));
    Eigen::Matrix4d t;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) {
        const ordered_json& x = m[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
        t(r, c) = x.is_null() ? std::numeric_limits<double>::quiet_NaN() : x.get<double>();
      }
    return t;
  }
  VisitTotals visits(const ordered_json& j, const std::string& where) const {
    VisitTotals v;
    const ordered_json& o = object(j, "visits", where);
    for_each_count(v, [&](const char* name, std::uint64_t& x) { x = count(o, name, where + "visits: "); });
    return v;
  }
  StageReport stage(const std::string& name, const ordered_json& st) const;

 private:
  const std::string& source_;
};

StageReport Reader::stage(const std::string& name, const ordered_json& st) const {
  const std::string where = "stage '" + visible_text(name) + "': ";
  need(st.is_object(), "stage '" + visible_text(name) + "' is not an object");
  StageReport s;
  s.name = name;
  s.seconds = number(st, "seconds", where);
  s.search = text(st, "search", where);
  if (s.search == "none") s.search.clear();
  SearchCounters& k = s.kdtree;
  k.searches = count(st, "searches", where);
  k.search_seconds = number(st, "search_seconds", where);
  if (!s.search.empty()) {
    k.neighbors = count(st, "neighbors", where);
    k.builds = count(st, "trees_built", where);
    k.build_seconds = number(st, "build_seconds", where);
    k.visits = visits(st, where);
    const ordered_json& l = object(st, "leaders", where);
    k.leaders = {count(l, "leaders", where), count(l, "followers", where), count(l, "leader_buffer_full", where)};
    const ordered_json& a = object(st, "accelerator", where);
    const std::string in = where + "accelerator: ";
    k.accel.jobs = count(a, "jobs", in);
    k.accel.queries = count(a, "queries", in);
    k.accel.fallback_searches = count(a, "fallback_searches", in);
    k.accel.fallback_seconds = number(a, "fallback_cpu_seconds", in);
    k.accel.cycles = count(a, "cycles", in);
    k.accel.modeled_search_seconds = number(a, "modeled_search_seconds", in);
    k.accel.modeled_host_seconds = number(a, "modeled_host_seconds", in);
    k.accel.energy_pj = number(a, "energy_pj", in);
    k.accel.visits = visits(a, in);
  }
  // What the writer derives or states is not kept; every other key is the stage's own count.
  static const std::set<std::string> kWritten{"seconds",   "search",      "searches",      "queries",
                                              "neighbors", "trees_built", "build_seconds", "search_seconds",
                                              "visits",    "leaders",     "visits_note",   "accelerator"};
  for (const auto& [key, v] : st.items())
    if (!kWritten.count(key)) s.info[key] = v;
  return s;
}

}  // namespace

Report report_from_json(const ordered_json& doc, const std::string& source) {
  const Reader in(source);
  in.need(doc.is_object(), "not a JSON object");
  if (doc.contains("version"))
    in.need(is_count(doc["version"]) && doc["version"].get<std::uint64_t>() >= 1 &&
                doc["version"].get<std::uint64_t>() <= static_cast<std::uint64_t>(Report::kVersion),
            "'version' is " + doc["version"].dump() + ", this tigris reads version " +
                std::to_string(Report::kVersion) + " and earlier");
  Report r;
  RegistrationResult& res = r.result;
  in.need(doc.contains("status") && doc["status"].is_string(), "no 'status' text");
  res.status = doc["status"].get<std::string>();
  res.problem = in.text(doc, "problem");
  in.need(doc.contains("transform") && (doc["transform"].is_null() || doc["transform"].is_array()), "no 'transform'");
  in.need(doc["transform"].is_null() == r.degenerate(),
          r.degenerate() ? "a degenerate registration has no 'transform' (null)"
                         : "'transform' is null, which only a degenerate registration has");
  res.transform = r.degenerate() ? Eigen::Matrix4d::Constant(std::numeric_limits<double>::quiet_NaN())
                                 : in.matrix(doc["transform"], "transform", true);
  if (doc.contains("initial_transform")) res.initial = in.matrix(doc["initial_transform"], "initial_transform", false);
  in.need(doc.contains("seconds") && doc["seconds"].is_number() && doc["seconds"].get<double>() >= 0,
          "no 'seconds' (a number, at least 0)");
  res.total_seconds = doc["seconds"].get<double>();
  in.need(doc.contains("stages") && doc["stages"].is_object() && !doc["stages"].empty(), "no 'stages'");
  for (const auto& [name, st] : doc["stages"].items()) res.stages.push_back(in.stage(name, st));

  for (auto [key, cloud] : {std::pair{"source", &r.source}, std::pair{"target", &r.target}}) {
    const ordered_json& c = in.object(doc, key);
    cloud->name = in.text(c, "name", std::string(key) + ": ");
    cloud->points = in.count(c, "points", std::string(key) + ": ");
  }
  r.preset = in.text(doc, "preset");
  r.search = in.text(doc, "search");
  const ordered_json& inj = in.object(doc, "injection");
  if (inj.contains("rpce_kth")) {
    in.need(is_count(inj["rpce_kth"]) && inj["rpce_kth"].get<std::uint64_t>() <= 1000000,
            "injection: 'rpce_kth' is not a rank");
    r.injection.rpce_kth = inj["rpce_kth"].get<int>();
  }
  if (inj.contains("normals_shell") && !inj["normals_shell"].is_null()) {
    const ordered_json& sh = inj["normals_shell"];
    in.need(sh.is_array() && sh.size() == 2 && sh[0].is_number() && sh[1].is_number(),
            "injection: 'normals_shell' is not [R1, R2]");
    r.injection.shell_inner = sh[0].get<double>();
    r.injection.shell_outer = sh[1].get<double>();
  }
  r.injection.normals_radius = in.number(inj, "normals_radius", "injection: ");
  const ordered_json& work = in.object(doc, "kdtree_work");
  r.work_spent = in.number(work, "distances_and_neighbors", "kdtree_work: ");
  r.max_work = in.number(work, "max_work", "kdtree_work: ");
  if (doc.contains("accelerator")) {
    const ordered_json& a = in.object(doc, "accelerator");
    Report::Accelerator acc;
    acc.sampling = a.value("sampling", ordered_json());
    acc.config = a.value("config", ordered_json());
    if (a.contains("job_list")) {
      in.need(a["job_list"].is_array() && std::all_of(a["job_list"].begin(), a["job_list"].end(),
                                                      [](const ordered_json& row) {
                                                        return row.is_object() && (!row.contains("sampled") ||
                                                                                   row["sampled"].is_boolean());
                                                      }),
              "accelerator: 'job_list' is not a list of jobs");
      acc.job_list = a["job_list"];
    }
    // Totals are the stages' sums; a count there that is not one is no report's.
    in.count(a, "fallback_searches", "accelerator: ");
    r.accelerator = acc;
  }
  if (doc.contains("ground_truth")) {
    const ordered_json& g = in.object(doc, "ground_truth");
    in.need(g.contains("transform"), "ground_truth: no 'transform'");
    r.truth =
        Report::Truth{in.text(g, "source", "ground_truth: "), in.matrix(g["transform"], "ground_truth.transform", true),
                      in.text(g, "warning", "ground_truth: ")};
  }
  r.config = nlohmann::json::parse(in.object(doc, "config").dump());
  r.trace = doc.value("trace", ordered_json());
  return r;
}

Report read_report(const std::string& path) {
  const std::string text = read_input(path, "a registration report", kMaxSettingsBytes);
  return report_from_json(parse_json_text<ordered_json>(text, path), path);
}

}  // namespace tigris::registration
