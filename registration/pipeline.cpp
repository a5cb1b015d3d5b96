// The pipeline's stage order, timing and per-stage search counters (pipeline.hpp).
#include <chrono>
#include <stdexcept>

#include "core/timer.hpp"
#include "stages.hpp"

namespace tigris::registration {
namespace {

using Clock = std::chrono::steady_clock;
using namespace stages;

Cloud::Ptr to_pcl(const PointCloud& c) {
  auto out = std::make_shared<Cloud>();
  out->reserve(c.size());
  for (const Point3& p : c) out->push_back(pcl::PointXYZ(p.x, p.y, p.z));
  return out;
}

// The search settings of a stage: approximate search only where the paper approximates
// (normals, RPCE); elsewhere the approx back-end searches exactly on the golden model.
SearchSettings settings_for(const PipelineConfig& c, bool approximable, const PipelineHooks& hooks) {
  SearchSettings s;
  s.budget = hooks.budget;
  s.recorder = hooks.recorder;
  s.backend = c.search.backend;
  if (s.backend == Backend::Approx && !approximable) s.backend = Backend::Exact;
  if (s.backend == Backend::Flann && hooks.accelerator)
    throw std::invalid_argument(
        "the accelerator in the loop runs the golden model's searches: search.backend must be "
        "exact or approx, not flann");
  s.accelerator = hooks.accelerator;
  s.top_height = c.search.top_height;
  s.nn_thd = static_cast<float>(c.search.nn_thd);
  s.radius_thd = static_cast<float>(c.search.radius_thd);
  s.leader_capacity = c.search.leader_capacity;
  s.leader_width = c.search.leader_width;
  s.leader_scope = c.search.leader_scope;
  s.leader_in_flight = c.search.leader_in_flight;
  return s;
}

// Times one stage and collects its counters into the result.
class StageRun {
 public:
  StageRun(RegistrationResult& r, const std::string& name, const StageCallback& cb, const SearchSettings* s)
      : result_(r), counters_(std::make_shared<SearchCounters>()), t0_(Clock::now()) {
    report_.name = name;
    if (s) report_.search = to_string(s->backend);
    if (cb) cb(name);
  }
  const Counters& counters() const { return counters_; }
  nlohmann::json& info() { return report_.info; }
  void done() {
    report_.seconds = seconds_since(t0_);
    report_.kdtree = *counters_;
    result_.stages.push_back(report_);
  }

 private:
  RegistrationResult& result_;
  Counters counters_;
  StageReport report_;
  Clock::time_point t0_;
};

}  // namespace

std::vector<StageInfo> stage_list() {
  std::vector<StageInfo> out;
  for (const StageDef& d : stage_table()) out.push_back(d.info);
  return out;
}

nlohmann::json stage_list_json() {
  nlohmann::json out = nlohmann::json::array();
  for (const StageInfo& s : stage_list()) {
    nlohmann::json j = {{"key", s.key}, {"title", s.title}};
    if (!s.parts.empty()) {
      j["parts"] = nlohmann::json::array();
      for (const StagePart& p : s.parts) j["parts"].push_back({{"title", p.title}, {"time", p.time}});
    }
    out.push_back(j);
  }
  return out;
}

RegistrationResult register_clouds(const PointCloud& source_points, const PointCloud& target_points,
                                   const PipelineConfig& c, const PipelineHooks& hooks) {
  const auto t_all = Clock::now();
  RegistrationResult r;
  validate(c, "registration configuration");
  const SearchSettings approximable = settings_for(c, true, hooks);
  PipelineState state{c,
                      settings_for(c, false, hooks),
                      approximable,
                      approximable,
                      to_pcl(source_points),
                      to_pcl(target_points),
                      {},
                      {},
                      {},
                      {},
                      {},
                      {},
                      {},
                      r};
  // Error injection only on the paper's injected searches: normal estimation (radius) and RPCE.
  state.normals_search.shell_inner = static_cast<float>(c.inject.normals_shell_inner);
  state.normals_search.shell_outer = static_cast<float>(c.inject.normals_shell_outer);
  state.rpce_search.inject_kth = c.inject.rpce_kth;
  state.normals_search.leaf_size = c.search.normals_leaf_size;  // the authors' per-stage leaf sizes
  state.rpce_search.leaf_size = c.search.rpce_leaf_size;
  // Every stage announces itself to the caller and to the trace recorder.
  const StageCallback on_stage = [&hooks](const std::string& stage) {
    if (hooks.recorder) hooks.recorder->begin_stage(stage);
    if (hooks.on_stage) hooks.on_stage(stage);
  };
  for (const StageDef& d : stage_table()) {
    if (d.enabled && !d.enabled(c)) continue;
    StageRun st(r, d.info.key, on_stage, d.searches ? d.searches(state) : nullptr);
    StageContext ctx{st.counters(), st.info()};
    d.run(state, ctx);
    st.done();
  }
  r.total_seconds = seconds_since(t_all);
  return r;
}

}  // namespace tigris::registration
