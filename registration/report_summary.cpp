#include "report_summary.hpp"

#include <cmath>
#include <optional>

namespace tigris::registration {

using nlohmann::ordered_json;

std::string injection_text(const Report::Injection& i) {
  std::string injection;
  if (i.rpce_kth > 1) injection += ", RPCE returns the K-th nearest (K = " + std::to_string(i.rpce_kth) + ")";
  if (i.shell_outer > 0) {
    char buf[96];
    std::snprintf(buf, sizeof buf, ", normals search the shell %g..%g m (r %g)", i.shell_inner, i.shell_outer,
                  i.normals_radius);
    injection += buf;
  }
  return injection;
}

namespace {

// The accelerator's figures per stage and in all, and whether jobs were sampled.
void print_loop(std::FILE* out, const Report& rep) {
  const RegistrationResult& r = rep.result;
  std::fprintf(out, "  on the accelerator (modeled; every job bit-exact against the golden model):\n");
  std::fprintf(out, "  %-16s %5s %9s %9s %12s %10s %10s %10s\n", "stage", "jobs", "queries", "fallback", "cycles",
               "kd s", "stage s", "energy uJ");
  for (const auto& s : r.stages) {
    if (s.search.empty()) continue;
    const auto& a = s.kdtree.accel;
    std::fprintf(out, "  %-16s %5llu %9llu %9llu %12llu %10.5f %10.4f %10.2f\n", s.name.c_str(),
                 static_cast<unsigned long long>(a.jobs), static_cast<unsigned long long>(a.queries),
                 static_cast<unsigned long long>(a.fallback_searches), static_cast<unsigned long long>(a.cycles),
                 modeled_kdtree_seconds(s.kdtree), modeled_stage_seconds(s), a.energy_pj * 1e-6);
  }
  const LoopFigures l = loop_figures(r);
  std::fprintf(out, "  end to end %.4f s modeled (KD-tree %.5f s, %.1f uJ); %.1f s of wall time, simulation included\n",
               l.modeled_e2e, l.modeled_kd, l.energy_pj * 1e-6, r.total_seconds);
}

// How the accelerator's jobs were simulated (after the summary: estimates must be read as such).
void print_sampling(std::FILE* out, const Report& rep) {
  const std::uint64_t sampled = rep.sampled_jobs(), jobs = loop_figures(rep.result).jobs;
  const ordered_json& a = rep.accelerator->sampling;
  const std::string setting = a.is_string() ? a.get<std::string>() : a.dump();
  if (sampled > 0)
    std::fprintf(out,
                 "  sampled %llu of %llu accelerator jobs (sim.sampling %s): their cycles and energy are estimates; "
                 "--accel-set sim.sampling=off simulates every query\n",
                 static_cast<unsigned long long>(sampled), static_cast<unsigned long long>(jobs), setting.c_str());
  else
    std::fprintf(out, "  every query of the %llu accelerator jobs simulated (sim.sampling %s%s)\n",
                 static_cast<unsigned long long>(jobs), setting.c_str(),
                 setting == "off" ? "" : ": no job long enough to sample");
}

}  // namespace

void print_summary(std::FILE* out, const Report& rep, const std::string& backend, const std::string& path) {
  const std::string injection = injection_text(rep.injection);
  const RegistrationResult& r = rep.result;
  std::fprintf(out, "tigris register: preset %s, search %s, %llu -> %llu points%s\n", rep.preset.c_str(),
               backend.c_str(), static_cast<unsigned long long>(rep.source.points),
               static_cast<unsigned long long>(rep.target.points), injection.c_str());
  std::fprintf(out, "  %-16s %9s %10s %11s\n", "stage", "seconds", "kd-queries", "kd-seconds");
  for (const auto& s : r.stages)
    std::fprintf(out, "  %-16s %9.3f %10llu %11.3f\n", s.name.c_str(), s.seconds,
                 static_cast<unsigned long long>(s.kdtree.searches), s.kdtree.search_seconds + s.kdtree.build_seconds);
  if (rep.in_loop())
    print_loop(out, rep);
  else
    std::fprintf(out, "  total %.3f s, KD-tree share %.1f%%\n", r.total_seconds,
                 100.0 * (r.total_seconds > 0 ? rep.kdtree_seconds() / r.total_seconds : 0.0));
  if (r.status != "degenerate") {
    std::fprintf(out, "  transform (target <- source)%s:\n", r.status == "converged" ? "" : ", NOT CONVERGED");
    for (int i = 0; i < 3; ++i)
      std::fprintf(out, "    %10.6f %10.6f %10.6f %10.4f\n", r.transform(i, 0), r.transform(i, 1), r.transform(i, 2),
                   r.transform(i, 3));
  }
  const std::optional<PoseError> err = rep.error();
  if (err && std::isfinite(err->translation_per_m))
    std::fprintf(
        out, "  error vs ground truth: translation %.4f m, rotation %.4f deg (%.4f m/m, %.4f deg/m over %.3f m)\n",
        err->translation_m, err->rotation_deg, err->translation_per_m, err->rotation_deg_per_m, err->travelled_m);
  else if (err)
    std::fprintf(out,
                 "  error vs ground truth: translation %.4f m, rotation %.4f deg (per metre: n/a, the ground truth "
                 "does not move)\n",
                 err->translation_m, err->rotation_deg);
  if (err && !rep.truth->warning.empty()) std::fprintf(out, "  warning: %s\n", rep.truth->warning.c_str());
  std::fprintf(out, "  wrote %s\n", path.c_str());
  if (rep.in_loop()) print_sampling(out, rep);
}

void print_job_line(std::FILE* out, std::uint64_t n, const AccelJob& job, const nlohmann::json& rep,
                    const std::string& stage) {
  const double modeled = rep.contains("modeled_seconds") ? rep["modeled_seconds"]["total"].get<double>() : 0.0;
  const nlohmann::json sampling = rep.value("sampling", nlohmann::json::object());
  const bool sampled = sampling.value("sampled", false);
  std::fprintf(
      out,
      "tigris register: %s: accelerator job %llu (%s, %zu queries on %zu points): %s, %s%.3g ms modeled, %.1f s "
      "simulated%s\n",
      stage.c_str(), static_cast<unsigned long long>(n), to_string(job.params.mode), job.queries->size(),
      job.points->size(), rep.value("verdict", "?").c_str(), sampled ? "~" : "", 1e3 * modeled,
      rep.value("wall_seconds", 0.0),
      sampled ? (" (sampled: " + std::to_string(sampling.value("simulated", 0)) + " queries simulated)").c_str() : "");
}

}  // namespace tigris::registration
