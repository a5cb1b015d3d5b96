// Records a registration's 3D searches into a workload trace (traces/workload_trace.hpp): the
// search plug-in reports every tree it builds and every search it answers, the pipeline the
// stage and ICP iteration they belong to, and the searches of one stage, iteration, tree and
// parameter set become one accelerator job (traces/README.md, "Jobs"). Jobs may interleave:
// reciprocal RPCE searches the target tree and then the source tree for each source point, so
// several jobs stay open until the stage or iteration ends; they are stored in the order of
// their first search.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "traces/workload_trace.hpp"

namespace tigris::registration {

class TraceRecorder {
 public:
  // The pipeline: a stage starts (ICP's iterations count from 0); ICP finished an iteration.
  void begin_stage(const std::string& stage);
  void next_iteration();

  // The plug-in: a tree was built on `points` (the finite input points in index order, the
  // indices its results use) by `backend` at `top_height`; returns the tree's serial.
  int tree_built(const PointCloud& points, const std::string& backend, int top_height, double build_seconds);
  // One search on tree `serial`, as issued (mode etc. in `shape`, whose counts/indices/seconds
  // are ignored), with the indices it returned into the tree's points.
  void searched(int serial, const trace::Job& shape, const Point3& query, const std::uint32_t* indices, std::size_t n,
                double seconds);

  // Time spent recording (copying results, hashing clouds): the trace's stage and total
  // seconds leave it out, so a recorded registration is timed as one without recording.
  void add_overhead(double seconds) { overhead_[stage_] += seconds; }
  double overhead(const std::string& stage) const {
    const auto it = overhead_.find(stage);
    return it == overhead_.end() ? 0.0 : it->second;
  }

  // Closes the last job and hands the trace over (stages and meta are the caller's to fill).
  trace::Trace finish();
  std::size_t jobs() const { return trace_.jobs.size() + open_.size(); }

 private:
  void close();  // the open jobs, in the order of their first search
  struct Tree {
    std::uint64_t hash;
    std::string backend;
    int top_height;
    double build_seconds;
    bool charged;  // its build seconds went to a job already
  };
  trace::Trace trace_;
  std::vector<Tree> trees_;
  std::string stage_;
  int iteration_ = -1;
  struct Open {
    trace::Job job;
    PointCloud queries;
  };
  std::vector<Open> open_;
  std::map<std::string, double> overhead_;
};

}  // namespace tigris::registration
