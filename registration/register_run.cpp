#include "register_run.hpp"

#include <cstdio>
#include <stdexcept>
#include <utility>

#include <pcl/console/print.h>

#include "core/out_folder.hpp"

namespace tigris::registration {

using nlohmann::ordered_json;

RegisterRun run_registration(const PointCloud& source, const PointCloud& target, const PipelineConfig& config,
                             double max_work, bool record, std::shared_ptr<AcceleratorPort> accelerator,
                             std::string& stage_now) {
  // PCL's own messages (e.g. SHOT's "local reference frame is not valid" per dropped key point)
  // would flood stderr: the counts are in registration.json instead.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  auto budget = std::make_shared<WorkBudget>();
  budget->limit = max_work;
  budget->progress = [&](const WorkBudget& b) {
    std::fprintf(stderr, "tigris register: %s: %llu searches so far, %.3g distances and neighbours (--max-work %.3g)\n",
                 stage_now.c_str(), static_cast<unsigned long long>(b.searches), b.spent, b.limit);
  };
  PipelineHooks hooks;
  hooks.on_stage = [&](const std::string& stage) {
    stage_now = stage;
    std::fprintf(stderr, "tigris register: %s...\n", stage.c_str());
  };
  hooks.budget = budget;
  hooks.accelerator = std::move(accelerator);
  RegisterRun run;
  if (record) run.recorder = hooks.recorder = std::make_shared<TraceRecorder>();
  try {
    run.result = register_clouds(source, target, config, hooks);
  } catch (const AcceleratorFailure& e) {
    std::fprintf(stderr, "tigris register: MISMATCH in stage %s: %s\n", stage_now.c_str(), e.what());
    run.mismatch = true;
  } catch (const WorkLimitExceeded& e) {
    throw std::invalid_argument(std::string(e.what()) + " in stage " + stage_now +
                                "; raise --max-work (0: no limit) if the registration is meant to be that large, or "
                                "check the injection, radii and k of the configuration");
  }
  run.work_spent = budget->spent;
  return run;
}

ordered_json write_trace(const std::string& path, TraceRecorder& recorder, const Report& report,
                         const std::string& command_line) {
  const RegistrationResult& r = report.result;
  const ordered_json doc = to_json(report);
  trace::Trace t = recorder.finish();
  t.meta = nlohmann::json::parse(
      doc.dump(-1, ' ', false,
               ordered_json::error_handler_t::replace));  // the registration's report, without its stages' details
  t.meta.erase("stages");
  t.meta["command_line"] = command_line;
  t.total_seconds = r.total_seconds;
  for (const auto& s : r.stages) {  // the time spent recording is not the registration's
    const double overhead = recorder.overhead(s.name);
    t.stages.push_back({s.name, s.seconds - overhead, s.kdtree.search_seconds, s.kdtree.build_seconds});
    t.total_seconds -= overhead;
  }
  t.meta["seconds"] = t.total_seconds;  // registration.json's, which includes the recording
  t.meta["seconds_recording"] = r.total_seconds - t.total_seconds;
  const std::vector<std::uint8_t> bytes = trace::encode(t);
  write_file(path, [&](std::ostream& f) {
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  });
  std::fprintf(stderr, "tigris register: trace %s: %zu jobs, %zu clouds\n", path.c_str(), t.jobs.size(),
               t.clouds.size());
  return {{"path", path}, {"jobs", t.jobs.size()}, {"clouds", t.clouds.size()}};
}

}  // namespace tigris::registration
