// The PCL search plug-in (docs/registration.md): a pcl::search::KdTree<PointT> subclass, so
// PCL's NormalEstimation, FPFH/SHOT estimation, CorrespondenceEstimation and
// IterativeClosestPoint accept it unchanged, that answers every search from the golden model
// (exact, or approximate leader/follower search, on a two-stage tree of a chosen top height) or,
// as the CPU baseline, from PCL's own KdTreeFLANN. It never builds a FLANN index unless asked
// for the baseline. Every search is counted (and timed) into the counters of its stage.
//
// Approximate search keeps leader state between calls (mutable behind PCL's const search
// methods): results depend on the order of the calls, so never use it from PCL's OMP classes.
//
// The template answers PCL's calls and keeps what depends on the point type; the rest is the
// same for every point type and has files of its own:
//  - search_settings.hpp: what a tree is asked to do (SearchSettings);
//  - search_counters.hpp: the stage's counters, the registration's work budget, charging a search;
//  - golden_tree.hpp: the golden tree over the input's finite points;
//  - injection.hpp: error injection (inject_kth, the shell), with its exact semantics;
//  - announced_jobs.hpp: the accelerator in the loop (expect_queries, then_expect);
//  - search_recording.hpp: the tree and its searches in a workload trace.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include <pcl/search/kdtree.h>

#include "accelerator_port.hpp"
#include "announced_jobs.hpp"
#include "core/timer.hpp"
#include "golden_tree.hpp"
#include "injection.hpp"
#include "pipeline_config.hpp"  // Backend
#include "search_counters.hpp"
#include "search_recording.hpp"
#include "search_settings.hpp"
#include "sw_ref/search.hpp"
#include "trace_recorder.hpp"

namespace tigris::registration {

// Hands the neighbours [first, last) (indices into a tree's points) to PCL: appends their
// input indices (`map`: a tree point's index in the input cloud) and squared distances, and
// refills `local` (null: not recording) with the tree's own indices, the trace's numbering.
// Returns how many.
int to_pcl_results(const Neighbor* first, const Neighbor* last, const std::vector<pcl::index_t>& map,
                   pcl::Indices& k_indices, std::vector<float>& k_sqr_distances, std::vector<std::uint32_t>* local);

template <typename PointT>
class TigrisKdTree : public pcl::search::KdTree<PointT> {
  using Base = pcl::search::KdTree<PointT>;
  using Clock = SteadyClock;

 public:
  using Ptr = std::shared_ptr<TigrisKdTree<PointT>>;
  using Base::nearestKSearch;
  using Base::radiusSearch;
  using typename Base::IndicesConstPtr;
  using typename Base::PointCloudConstPtr;

  TigrisKdTree(const SearchSettings& settings, std::shared_ptr<SearchCounters> counters)
      : Base(true), settings_(settings), counters_(std::move(counters)) {
    settings_.validate_injection();
  }

  // The counters searches are charged to (the pipeline switches them per stage).
  void set_counters(std::shared_ptr<SearchCounters> counters) { counters_ = std::move(counters); }
  const std::shared_ptr<SearchCounters>& counters() const { return counters_; }

  // Accelerator in the loop (announced_jobs.hpp): the points of the searches about to come, in
  // the order PCL will make them (`indices`: a subset, in that order; null: all), run as one
  // job. Non-finite points are not announced (they get no neighbours, as always). The
  // announcement outlives a rebuild of the tree.
  // An announced set is a new job on every back-end: approximate search starts it with an
  // empty Leader Buffer, as the accelerator does (so ICP's iterations do not inherit each
  // other's leaders, and the CPU's approximate results are the in-the-loop ones).
  void expect_queries(const pcl::PointCloud<PointT>& cloud, const pcl::Indices* indices = nullptr) {
    golden_.forget_leaders();
    if (!settings_.accelerator) return;
    PointCloud queries;
    const auto add = [&](const PointT& p) {
      if (finite(p)) queries.push_back(to_point(p));
    };
    if (indices)
      for (pcl::index_t i : *indices) add(cloud[static_cast<std::size_t>(i)]);
    else
      for (const PointT& p : cloud) add(p);
    jobs_.announce(std::move(queries));
  }
  bool accelerated() const { return settings_.accelerator != nullptr; }
  // Announces the set after the current one (a queue): `announce` is called when the current
  // set is used up and a search is not its first point again, and calls expect_queries; it may
  // read the jobs run so far (FPFH: its SPFH pass searches the key points' neighbours).
  void then_expect(std::function<void()> announce) {
    if (settings_.accelerator) jobs_.then(std::move(announce));
  }
  // Starts the announced set's job now, with the parameters its searches will ask: kNN
  // searches of `k`, or radius searches of `radius` and `max_nn` (AcceleratorPort::prefetch),
  // so that it runs beside the jobs before it (the other cloud's, in a stage that searches
  // both). Nothing without an accelerator in the loop; a job its searches do not ask is not used.
  void prefetch_knn(int k) const {
    if (!settings_.accelerator || settings_.backend == Backend::Flann || k < 1) return;
    const KthInjection kth = kth_injection(settings_, k);
    SearchParams p;
    p.mode = kth.want == 1 ? Mode::NN : Mode::KNN;
    p.k = kth.want;
    jobs_.prefetch(golden_params(p, settings_), golden_, *settings_.accelerator);
  }
  void prefetch_radius(double radius, unsigned int max_nn = 0) const {
    if (!settings_.accelerator || settings_.backend == Backend::Flann || !(radius > 0.0)) return;
    const ShellInjection shell = shell_injection(settings_, radius, max_nn);
    SearchParams p;
    p.mode = Mode::Radius;
    p.radius = static_cast<float>(shell.radius);
    p.max_nn = shell.max_nn;
    jobs_.prefetch(golden_params(p, settings_), golden_, *settings_.accelerator);
  }
  // The input indices of every neighbour the last job returned, sorted, each once.
  pcl::Indices last_job_neighbors() const { return jobs_.last_job_neighbors(map_); }

  void setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices = IndicesConstPtr()) override {
    const auto t0 = Clock::now();
    if (settings_.backend == Backend::Flann) {
      Base::setInputCloud(cloud, indices);
    } else {
      this->input_ = cloud;
      this->indices_ = indices;
      PointCloud pts = finite_points();
      const int height = settings_.height_for(pts.size());
      golden_.build(std::move(pts), height);
      jobs_.rebuilt();  // an announced set is searched on the new tree
    }
    const double seconds = seconds_since(t0);
    ++counters_->builds;
    counters_->build_seconds += seconds;
    if (settings_.recorder) {
      const auto t1 = Clock::now();
      const PointCloud pts = finite_points();
      recording_.tree_built(settings_, pts, map_, this->input_->size(), seconds, t1);
    }
  }

  int nearestKSearch(const PointT& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override {
    const auto t0 = Clock::now();
    if (!finite(point)) return none(k_indices, k_sqr_distances, t0);
    const KthInjection kth = kth_injection(settings_, k);
    int n;
    if (settings_.backend == Backend::Flann) {
      n = Base::nearestKSearch(point, kth.want, k_indices, k_sqr_distances);
    } else {
      SearchParams p;
      p.mode = kth.want == 1 ? Mode::NN : Mode::KNN;
      p.k = kth.want;
      n = golden(p, point, k_indices, k_sqr_distances);
    }
    if (settings_.recorder)
      recording_.searched(settings_, knn_shape(kth.want, settings_), to_point(point), k_indices, n, t0);
    n = drop_nearest(kth, k, n, k_indices, k_sqr_distances);
    charge(n, t0);
    return n;
  }

  int radiusSearch(const PointT& point, double radius, pcl::Indices& k_indices, std::vector<float>& k_sqr_distances,
                   unsigned int max_nn = 0) const override {
    const auto t0 = Clock::now();
    if (!finite(point)) return none(k_indices, k_sqr_distances, t0);
    const ShellInjection shell = shell_injection(settings_, radius, max_nn);
    int n;
    if (settings_.backend == Backend::Flann) {
      n = Base::radiusSearch(point, shell.radius, k_indices, k_sqr_distances, shell.max_nn);
    } else {
      SearchParams p;
      p.mode = Mode::Radius;
      p.radius = static_cast<float>(shell.radius);
      p.max_nn = shell.max_nn;
      n = golden(p, point, k_indices, k_sqr_distances);
    }
    if (settings_.recorder)
      recording_.searched(settings_, radius_shape(shell.radius, shell.max_nn, shell.shell, settings_), to_point(point),
                          k_indices, n, t0);
    if (shell.shell) n = keep_shell(settings_, max_nn, n, k_indices, k_sqr_distances);
    charge(n, t0);
    return n;
  }

 private:
  // A point with a NaN or infinite coordinate has no neighbours; PCL's FLANN would assert on it.
  static bool finite(const PointT& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }
  static Point3 to_point(const PointT& p) { return {p.x, p.y, p.z}; }

  int none(pcl::Indices& k_indices, std::vector<float>& k_sqr_distances, Clock::time_point t0) const {
    k_indices.clear();
    k_sqr_distances.clear();
    charge(0, t0);
    return 0;
  }
  // Counts a search; `t0` its start, less the time spent recording it (not the search's cost).
  void charge(int n, Clock::time_point t0) const {
    const double recording = recording_.take_seconds();
    charge_search(*counters_, settings_.budget.get(), n, t0, recording, std::exchange(last_distances_, 0.0));
  }

  // The finite points of the input in index order (PCL's FLANN skips the others too); map_
  // takes such a point's index back to the input cloud's.
  PointCloud finite_points() {
    map_.clear();
    PointCloud pts;
    const auto add = [&](pcl::index_t i) {
      const PointT& p = (*this->input_)[static_cast<std::size_t>(i)];
      if (finite(p)) {
        pts.push_back(to_point(p));
        map_.push_back(i);
      }
    };
    if (this->indices_)
      for (pcl::index_t i : *this->indices_) add(i);
    else
      for (std::size_t i = 0; i < this->input_->size(); ++i) add(static_cast<pcl::index_t>(i));
    return pts;
  }

  // The golden model's answer: from the announced set's job when this is its next search, else
  // on the CPU (a fallback when the accelerator is in the loop).
  int golden(const SearchParams& asked, const PointT& point, pcl::Indices& k_indices,
             std::vector<float>& k_sqr_distances) const {
    k_indices.clear();
    k_sqr_distances.clear();
    if (!golden_.built() || !finite(point) || (asked.mode != Mode::Radius && asked.k < 1) ||
        (asked.mode == Mode::Radius && !(asked.radius > 0.0f)))
      return 0;
    const SearchParams p = golden_params(asked, settings_);
    const Point3 q = to_point(point);
    std::vector<std::uint32_t>* local = settings_.recorder ? &recording_.golden_local() : nullptr;
    if (settings_.accelerator) {
      jobs_.announce_next();
      if (const auto served = jobs_.serve(p, q, golden_, *settings_.accelerator, counters_->accel)) {
        last_distances_ = 0.0;  // the accelerator's work, bounded by its own guard
        return to_pcl_results(served->first, served->last, map_, k_indices, k_sqr_distances, local);
      }
    }
    const auto t_fallback = Clock::now();
    const std::vector<Neighbor>& found = golden_.search(p, q, *counters_, last_distances_);
    const int n = to_pcl_results(found.data(), found.data() + found.size(), map_, k_indices, k_sqr_distances, local);
    if (settings_.accelerator) {
      ++counters_->accel.fallback_searches;
      counters_->accel.fallback_seconds += seconds_since(t_fallback);
    }
    return n;
  }

  SearchSettings settings_;
  std::shared_ptr<SearchCounters> counters_;
  GoldenTree golden_;
  std::vector<pcl::index_t> map_;        // a finite point's index in the input cloud (finite_points)
  mutable double last_distances_ = 0.0;  // the golden search's distances, for the budget
  mutable SearchRecording recording_;
  mutable AnnouncedJobs jobs_;
};

}  // namespace tigris::registration
