#include "trace_recorder.hpp"
#include "core/timer.hpp"

#include <algorithm>
#include <chrono>

namespace tigris::registration {

namespace {

// Same job: one stage, iteration and tree, one parameter set.
bool same_shape(const trace::Job& a, const trace::Job& b) {
  return a.stage == b.stage && a.iteration == b.iteration && a.tree_serial == b.tree_serial && a.mode == b.mode &&
         a.k == b.k && a.radius == b.radius && a.max_nn == b.max_nn && a.approximate == b.approximate &&
         a.approx_thd == b.approx_thd && a.leader_capacity == b.leader_capacity && a.leader_width == b.leader_width &&
         a.leader_scope == b.leader_scope && a.leader_in_flight == b.leader_in_flight && a.inject_kth == b.inject_kth &&
         a.shell_inner == b.shell_inner && a.shell_outer == b.shell_outer;
}

}  // namespace

// Closing jobs hashes their query clouds: recording's time, counted in the stage it falls in.
void TraceRecorder::next_iteration() {
  const auto t0 = std::chrono::steady_clock::now();
  close();
  ++iteration_;
  add_overhead(seconds_since(t0));
}

void TraceRecorder::begin_stage(const std::string& stage) {
  const auto t0 = std::chrono::steady_clock::now();
  close();
  stage_ = stage;
  iteration_ = stage == "icp" ? 0 : -1;
  add_overhead(seconds_since(t0));
}

int TraceRecorder::tree_built(const PointCloud& points, const std::string& backend, int top_height,
                              double build_seconds) {
  trees_.push_back({trace_.add_cloud(points), backend, top_height, build_seconds, false});
  return static_cast<int>(trees_.size()) - 1;
}

void TraceRecorder::searched(int serial, const trace::Job& shape, const Point3& query, const std::uint32_t* indices,
                             std::size_t n, double seconds) {
  Tree& tree = trees_.at(static_cast<std::size_t>(serial));
  trace::Job key = shape;
  key.stage = stage_;
  key.iteration = iteration_;
  key.tree_serial = serial;
  auto it = std::find_if(open_.begin(), open_.end(), [&](const Open& o) { return same_shape(o.job, key); });
  if (it == open_.end()) {
    Open o;
    o.job = key;
    o.job.counts.clear();
    o.job.indices.clear();
    o.job.search_seconds = 0.0;
    o.job.tree = tree.hash;
    o.job.backend = tree.backend;
    o.job.top_height = tree.top_height;
    o.job.build_seconds = tree.charged ? 0.0 : tree.build_seconds;
    tree.charged = true;
    open_.push_back(std::move(o));
    it = open_.end() - 1;
  }
  it->queries.push_back(query);
  it->job.counts.push_back(static_cast<std::uint32_t>(n));
  it->job.indices.insert(it->job.indices.end(), indices, indices + n);
  it->job.search_seconds += seconds;
}

void TraceRecorder::close() {
  for (Open& o : open_) {
    o.job.queries = trace_.add_cloud(o.queries);
    trace_.jobs.push_back(std::move(o.job));
  }
  open_.clear();
}

trace::Trace TraceRecorder::finish() {
  close();
  return std::move(trace_);
}

}  // namespace tigris::registration
