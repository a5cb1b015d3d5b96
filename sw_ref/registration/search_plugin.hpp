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
// Error injection (the paper's section "Quantifying the error-tolerance", Figure 5), off by
// default and exact on the exact back-ends (golden exact, FLANN):
//  - inject_kth = K > 1: a k-nearest search returns the neighbours of rank K .. K+k-1 in the
//    canonical (dist2, index) order instead of ranks 1 .. k, so an NN search (k = 1) returns the
//    K-th nearest neighbour. It searches k+K-1 neighbours and drops the first K-1; a cloud with
//    fewer than K points gives its farthest point (an NN search never comes back empty, which
//    PCL's CorrespondenceEstimation relies on).
//  - shell_outer > 0: a radius search returns every point with R1^2 <= dist2 <= R2^2 (R1 =
//    shell_inner, R2 = shell_outer, squared in float32 as r2 in docs/model.md's numeric contract), in
//    canonical order, then max_nn truncation, instead of the ball of the requested radius
//    (which is ignored). It searches the ball of R2 and drops the points closer than R1.
// On the approx back-end both would apply to the approximate results; the pipeline rejects that
// combination (pipeline_config.hpp, validate).
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <pcl/search/kdtree.h>

#include "sw_ref/kdtree.hpp"
#include "accelerator_port.hpp"
#include "pipeline_config.hpp"  // Backend
#include "sw_ref/search.hpp"
#include "trace_recorder.hpp"

namespace tigris::registration {

// A new id for every plug-in tree build, whatever its point type (the host resends the tree
// image when a job's id differs from the last job's). Single-threaded pipeline.
inline std::uint64_t next_tree_id() {
  static std::uint64_t id = 0;
  return ++id;
}

// The work bound of a whole registration (issue 18): every search adds the distances it
// computed (golden back-ends: top-tree nodes, leaf and follower points) and the neighbours it
// returned (all back-ends; FLANN counts only these). Above `limit` (0: none) the search throws
// WorkLimitExceeded, so an injected K of 100,000 or a 100 m shell stops with a message instead
// of running for minutes; `progress` is called about every 2 s of searching.
struct WorkBudget {
  double limit = 0.0;
  double spent = 0.0;
  std::uint64_t searches = 0;
  std::function<void(const WorkBudget&)> progress;
  std::chrono::steady_clock::time_point last_report = std::chrono::steady_clock::now();
};

class WorkLimitExceeded : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct SearchSettings {
  Backend backend = Backend::Exact;
  int top_height = 10;          // clamped to each cloud's full height
  float nn_thd = 1.2f;          // approximate NN/kNN: follow a leader this close (metres)
  float radius_thd = 0.4f;      // approximate radius: threshold as a fraction of r
  int leader_capacity = 16;
  int leader_width = 0;         // R for NN/kNN (0: k)
  LeaderScope leader_scope = LeaderScope::FirstLeaf;
  LeaderInFlight leader_in_flight = LeaderInFlight::Wait;
  // Error injection (see the top of this file); the defaults inject nothing.
  int inject_kth = 1;           // k-nearest searches return ranks K .. K+k-1 (>= 1)
  float shell_inner = 0.0f;     // radius searches return R1 <= d <= R2 (metres, >= 0, < outer)
  float shell_outer = 0.0f;     // 0: no shell
  std::shared_ptr<WorkBudget> budget;  // shared by every tree of a registration; null: none
  std::shared_ptr<TraceRecorder> recorder;  // records every tree and search; null: none
  // In the loop (see "Accelerator in the loop" below): golden back-ends only; null: none.
  std::shared_ptr<AcceleratorPort> accelerator;

  bool injects_kth() const { return inject_kth > 1; }
  bool injects_shell() const { return shell_outer > 0.0f; }
  // Throws std::invalid_argument naming the field: inject_kth < 1, a shell with inner < 0,
  // inner >= outer or a non-finite bound.
  void validate_injection() const;
};

// What one pipeline stage's searches cost. `searches` counts query points searched (PCL's
// batch calls loop over single ones), `builds` the trees built (one per input cloud set).
struct SearchCounters {
  std::uint64_t searches = 0, neighbors = 0, builds = 0;
  double search_seconds = 0.0, build_seconds = 0.0;
  VisitTotals visits;    // golden back-ends only
  LeaderTotals leaders;  // approximate only
  // With the accelerator in the loop: the jobs it ran and what they cost in the model, and the
  // searches it could not batch (answered by the golden model on the CPU, their seconds kept).
  // search_seconds then holds the jobs' simulation wall time too: not a CPU cost.
  struct Accelerated {
    std::uint64_t jobs = 0, queries = 0, cycles = 0, fallback_searches = 0;
    double modeled_search_seconds = 0.0, modeled_host_seconds = 0.0, energy_pj = 0.0;
    double fallback_seconds = 0.0;
    VisitTotals visits;  // the accelerator's
  } accel;
};

template <typename PointT>
class TigrisKdTree : public pcl::search::KdTree<PointT> {
  using Base = pcl::search::KdTree<PointT>;
  using Clock = std::chrono::steady_clock;

 public:
  using Ptr = std::shared_ptr<TigrisKdTree<PointT>>;
  using typename Base::IndicesConstPtr;
  using typename Base::PointCloudConstPtr;
  using Base::nearestKSearch;
  using Base::radiusSearch;

  TigrisKdTree(const SearchSettings& settings, std::shared_ptr<SearchCounters> counters)
      : Base(true), settings_(settings), counters_(std::move(counters)) {
    settings_.validate_injection();
  }

  // The counters searches are charged to (the pipeline switches them per stage).
  void set_counters(std::shared_ptr<SearchCounters> counters) { counters_ = std::move(counters); }
  const std::shared_ptr<SearchCounters>& counters() const { return counters_; }

  // Accelerator in the loop (issue 19): the pipeline announces the points of the searches about
  // to come, in the order PCL will make them (`indices`: a subset, in that order; null: all).
  // The first search of the first announced point runs them all as one accelerator job with
  // that search's parameters; the calls that follow are served from the job's results while
  // each asks for the next announced point with the same parameters. A set runs once: a stage
  // that searches the same points again announces them again (expect_queries or then_expect).
  // Any other search is answered by the golden model on the CPU and counted as a fallback. Non-finite points are not announced (they get no neighbours, as always). The
  // announcement outlives a rebuild of the tree.
  // An announced set is a new job on every back-end: approximate search starts it with an
  // empty Leader Buffer, as the accelerator does (so ICP's iterations do not inherit each
  // other's leaders, and the CPU's approximate results are the in-the-loop ones).
  void expect_queries(const pcl::PointCloud<PointT>& cloud, const pcl::Indices* indices = nullptr) {
    searchers_.clear();
    if (!settings_.accelerator) return;
    expected_.clear();
    const auto add = [&](const PointT& p) {
      if (finite(p)) expected_.push_back({p.x, p.y, p.z});
    };
    if (indices)
      for (pcl::index_t i : *indices) add(cloud[static_cast<std::size_t>(i)]);
    else
      for (const PointT& p : cloud) add(p);
    batch_ran_ = false;
    cursor_ = 0;
  }
  bool accelerated() const { return settings_.accelerator != nullptr; }
  // Announces the set after the current one (a queue): `announce` is called when the current
  // set is used up and a search is not its first point again, and calls expect_queries; it may
  // read the jobs run so far (FPFH: its SPFH pass searches the key points' neighbours).
  void then_expect(std::function<void()> announce) {
    if (settings_.accelerator) pending_.push_back(std::move(announce));
  }
  // The input indices of every neighbour the last job returned, sorted, each once.
  pcl::Indices last_job_neighbors() const {
    pcl::Indices out;
    out.reserve(batch_.results.neighbors.size());
    for (const Neighbor& n : batch_.results.neighbors) out.push_back(map_[n.index]);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  void setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices = IndicesConstPtr()) override {
    const auto t0 = Clock::now();
    if (settings_.backend == Backend::Flann) {
      Base::setInputCloud(cloud, indices);
    } else {
      this->input_ = cloud;
      this->indices_ = indices;
      build_golden();
      batch_ran_ = false;  // an announced set is searched on the new tree
      cursor_ = 0;
    }
    const double seconds = seconds_since(t0);
    ++counters_->builds;
    counters_->build_seconds += seconds;
    if (settings_.recorder) {
      // The trace stores the points the golden tree is built on; FLANN's results are mapped
      // into the same numbering.
      const auto t1 = Clock::now();
      const PointCloud pts = finite_points();
      if (settings_.backend == Backend::Flann) {
        local_of_.assign(this->input_->size(), -1);
        for (std::size_t i = 0; i < map_.size(); ++i) local_of_[static_cast<std::size_t>(map_[i])] = static_cast<int>(i);
      }
      serial_ = settings_.recorder->tree_built(pts, to_string(settings_.backend), settings_.top_height, seconds);
      settings_.recorder->add_overhead(seconds_since(t1));
    }
  }

  int nearestKSearch(const PointT& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override {
    const auto t0 = Clock::now();
    if (!finite(point)) return none(k_indices, k_sqr_distances, t0);
    // Injection: search k + K - 1 and keep ranks K .. K+k-1 (the farthest when fewer than K).
    const int skip = settings_.injects_kth() && k >= 1 ? settings_.inject_kth - 1 : 0;
    const int want = k + skip;
    int n;
    if (settings_.backend == Backend::Flann) {
      n = Base::nearestKSearch(point, want, k_indices, k_sqr_distances);
    } else {
      SearchParams p;
      p.mode = want == 1 ? Mode::NN : Mode::KNN;
      p.k = want;
      n = golden(p, point, k_indices, k_sqr_distances);
    }
    if (settings_.recorder) {
      trace::Job shape;
      shape.mode = want == 1 ? "nn" : "knn";
      shape.k = want;
      shape.inject_kth = settings_.inject_kth;
      record(shape, point, k_indices, n, t0);
    }
    if (skip > 0 && n > 0) {
      const int drop = std::min(skip, n - 1);
      const int keep = std::min(n - drop, k);
      k_indices.erase(k_indices.begin(), k_indices.begin() + drop);
      k_sqr_distances.erase(k_sqr_distances.begin(), k_sqr_distances.begin() + drop);
      k_indices.resize(static_cast<std::size_t>(keep));
      k_sqr_distances.resize(static_cast<std::size_t>(keep));
      n = keep;
    }
    charge(n, t0);
    return n;
  }

  int radiusSearch(const PointT& point, double radius, pcl::Indices& k_indices,
                   std::vector<float>& k_sqr_distances, unsigned int max_nn = 0) const override {
    const auto t0 = Clock::now();
    if (!finite(point)) return none(k_indices, k_sqr_distances, t0);
    // Injection: the ball of R2, all of it (max_nn applies to the shell), minus d < R1.
    const bool shell = settings_.injects_shell();
    const double search_radius = shell ? static_cast<double>(settings_.shell_outer) : radius;
    const unsigned int search_max_nn = shell ? 0u : max_nn;
    int n;
    if (settings_.backend == Backend::Flann) {
      n = Base::radiusSearch(point, search_radius, k_indices, k_sqr_distances, search_max_nn);
    } else {
      SearchParams p;
      p.mode = Mode::Radius;
      p.radius = static_cast<float>(search_radius);
      p.max_nn = search_max_nn;
      n = golden(p, point, k_indices, k_sqr_distances);
    }
    if (settings_.recorder) {
      trace::Job shape;
      shape.mode = "radius";
      shape.radius = static_cast<float>(search_radius);
      shape.max_nn = search_max_nn;
      shape.shell_inner = shell ? settings_.shell_inner : 0.0f;
      shape.shell_outer = shell ? settings_.shell_outer : 0.0f;
      record(shape, point, k_indices, n, t0);
    }
    if (shell) {
      const float r1_2 = settings_.shell_inner * settings_.shell_inner;
      std::size_t kept = 0;
      for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) {
        if (!(k_sqr_distances[i] >= r1_2)) continue;
        if (max_nn > 0 && kept == max_nn) break;
        k_indices[kept] = k_indices[i];
        k_sqr_distances[kept] = k_sqr_distances[i];
        ++kept;
      }
      k_indices.resize(kept);
      k_sqr_distances.resize(kept);
      n = static_cast<int>(kept);
    }
    charge(n, t0);
    return n;
  }

 private:
  static double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
  }
  // A point with a NaN or infinite coordinate has no neighbours; PCL's FLANN would assert on it.
  static bool finite(const PointT& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }
  int none(pcl::Indices& k_indices, std::vector<float>& k_sqr_distances, Clock::time_point t0) const {
    k_indices.clear();
    k_sqr_distances.clear();
    charge(0, t0);
    return 0;
  }
  // Counts a search; `t0` its start, less the time spent recording it (not the search's cost).
  void charge(int n, Clock::time_point t0) const {
    ++counters_->searches;
    counters_->neighbors += static_cast<std::uint64_t>(n > 0 ? n : 0);
    counters_->search_seconds += seconds_since(t0) - recording_seconds_;
    recording_seconds_ = 0.0;
    if (WorkBudget* b = settings_.budget.get()) {
      b->spent += static_cast<double>(n > 0 ? n : 0) + last_distances_;
      last_distances_ = 0.0;
      if (++b->searches % 4096 == 0 && b->progress &&
          Clock::now() - b->last_report >= std::chrono::seconds(2)) {
        b->last_report = Clock::now();
        b->progress(*b);
      }
      if (b->limit > 0.0 && b->spent > b->limit) {
        char msg[320];
        std::snprintf(msg, sizeof msg,
                      "the registration's KD-tree searches have computed and returned more than %.3g "
                      "distances and neighbours (%llu searches), above --max-work %.3g",
                      b->spent, static_cast<unsigned long long>(b->searches), b->limit);
        throw WorkLimitExceeded(msg);
      }
    }
  }

  // The finite points of the input in index order (PCL's FLANN skips the others too); map_
  // takes such a point's index back to the input cloud's.
  PointCloud finite_points() {
    map_.clear();
    PointCloud pts;
    const auto add = [&](pcl::index_t i) {
      const PointT& p = (*this->input_)[static_cast<std::size_t>(i)];
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
        pts.push_back({p.x, p.y, p.z});
        map_.push_back(i);
      }
    };
    if (this->indices_)
      for (pcl::index_t i : *this->indices_) add(i);
    else
      for (std::size_t i = 0; i < this->input_->size(); ++i) add(static_cast<pcl::index_t>(i));
    return pts;
  }

  // One search into the trace: its results in the trace's numbering (the finite points).
  void record(trace::Job& shape, const PointT& point, const pcl::Indices& k_indices, int n, Clock::time_point t0) const {
    if (settings_.backend == Backend::Approx) {
      shape.approximate = true;
      shape.approx_thd = shape.mode == "radius" ? settings_.radius_thd * shape.radius : settings_.nn_thd;
      shape.leader_capacity = settings_.leader_capacity;
      shape.leader_width = settings_.leader_width;
      shape.leader_scope = to_string(settings_.leader_scope);
      shape.leader_in_flight = to_string(settings_.leader_in_flight);
    }
    if (settings_.backend == Backend::Flann) {
      local_.clear();
      for (int i = 0; i < n; ++i) local_.push_back(static_cast<std::uint32_t>(local_of_[static_cast<std::size_t>(k_indices[static_cast<std::size_t>(i)])]));
    }
    const std::uint32_t* idx = settings_.backend == Backend::Flann ? local_.data() : golden_local_.data();
    const auto t1 = Clock::now();
    settings_.recorder->searched(serial_, shape, {point.x, point.y, point.z}, idx, static_cast<std::size_t>(n > 0 ? n : 0),
                                 std::chrono::duration<double>(t1 - t0).count());
    recording_seconds_ = seconds_since(t1);
    settings_.recorder->add_overhead(recording_seconds_);
  }

  // The golden tree over finite_points().
  void build_golden() {
    searchers_.clear();
    points_ = finite_points();
    tree_.reset();
    tree_id_ = next_tree_id();
    if (points_.empty()) return;
    const int height = std::min(settings_.top_height, full_height_for(points_.size()));
    tree_ = std::make_unique<KdTree>(build_kdtree(points_, height));
  }

  int golden(SearchParams p, const PointT& point, pcl::Indices& k_indices, std::vector<float>& k_sqr_distances) const {
    k_indices.clear();
    k_sqr_distances.clear();
    if (!tree_ || !std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z) ||
        (p.mode != Mode::Radius && p.k < 1) || (p.mode == Mode::Radius && !(p.radius > 0.0f)))
      return 0;
    if (settings_.backend == Backend::Approx) {
      p.approximate = true;
      p.approx_thd = p.mode == Mode::Radius ? settings_.radius_thd * p.radius : settings_.nn_thd;
      p.leader_capacity = settings_.leader_capacity;
      p.leader_width = settings_.leader_width;
      p.leader_scope = settings_.leader_scope;
      p.leader_in_flight = settings_.leader_in_flight;
    }
    if (settings_.accelerator) {
      const int n = from_batch(p, point, k_indices, k_sqr_distances);
      if (n >= 0) return n;
    }
    const auto t_fallback = Clock::now();
    const int n = golden_cpu(p, point, k_indices, k_sqr_distances);
    if (settings_.accelerator) {
      ++counters_->accel.fallback_searches;
      counters_->accel.fallback_seconds += seconds_since(t_fallback);
    }
    return n;
  }

  static bool same_point(const Point3& a, const PointT& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
  static bool same_params(const SearchParams& a, const SearchParams& b) {
    return a.mode == b.mode && a.k == b.k && a.radius == b.radius && a.max_nn == b.max_nn &&
           a.approximate == b.approximate && a.approx_thd == b.approx_thd &&
           a.leader_capacity == b.leader_capacity && a.leader_width == b.leader_width &&
           a.leader_scope == b.leader_scope && a.leader_in_flight == b.leader_in_flight;
  }

  // Serves a search from the announced set's job (running it first when this is its first
  // point); -1 when the search is not the next announced one.
  int from_batch(const SearchParams& p, const PointT& point, pcl::Indices& k_indices,
                 std::vector<float>& k_sqr_distances) const {
    if (batch_ran_ && cursor_ == expected_.size() && !pending_.empty()) {
      const std::function<void()> announce = std::move(pending_.front());
      pending_.pop_front();
      announce();  // the next set (expect_queries)
    }
    if (expected_.empty()) return -1;
    if (!batch_ran_ && same_point(expected_.front(), point)) {
      AccelJob job;
      job.tree_id = tree_id_;
      job.points = &points_;
      job.top_height = tree_->top_height;
      job.queries = &expected_;
      job.params = p;
      batch_ = settings_.accelerator->run(job);
      if (batch_.results.num_queries() != expected_.size())
        throw AcceleratorFailure("the accelerator answered " + std::to_string(batch_.results.num_queries()) +
                                 " of a job's " + std::to_string(expected_.size()) + " queries");
      batch_params_ = p;
      batch_ran_ = true;
      cursor_ = 0;
      SearchCounters::Accelerated& a = counters_->accel;
      ++a.jobs;
      a.queries += expected_.size();
      a.cycles += batch_.cycles;
      a.modeled_search_seconds += batch_.search_seconds;
      a.modeled_host_seconds += batch_.host_seconds;
      a.energy_pj += batch_.energy_pj;
      a.visits.top += batch_.visits.top;
      a.visits.pruned += batch_.visits.pruned;
      a.visits.leaf_visits += batch_.visits.leaf_visits;
      a.visits.leaf_points += batch_.visits.leaf_points;
      a.visits.follower_points += batch_.visits.follower_points;
      a.visits.leader_checks += batch_.visits.leader_checks;
    }
    if (!batch_ran_ || cursor_ >= expected_.size() || !same_point(expected_[cursor_], point) ||
        !same_params(p, batch_params_))
      return -1;
    golden_local_.clear();
    for (const Neighbor* n = batch_.results.begin(cursor_); n != batch_.results.end(cursor_); ++n) {
      k_indices.push_back(map_[n->index]);
      k_sqr_distances.push_back(n->dist2);
      if (settings_.recorder) golden_local_.push_back(n->index);
    }
    last_distances_ = 0.0;  // the accelerator's work, bounded by its own guard
    ++cursor_;
    return static_cast<int>(k_indices.size());
  }

  // The golden model on the CPU.
  int golden_cpu(const SearchParams& p, const PointT& point, pcl::Indices& k_indices,
                 std::vector<float>& k_sqr_distances) const {
    // One Searcher (and one leader state) per distinct search: mode, k, radius, max_nn.
    auto& s = searchers_[std::make_tuple(static_cast<int>(p.mode), p.k, p.radius, p.max_nn)];
    if (!s) s = std::make_unique<Searcher>(*tree_, p);
    const LeaderTotals lead_before = s->leaders();
    s->search({point.x, point.y, point.z}, found_);
    counters_->visits.add(s->last_visits());
    last_distances_ = static_cast<double>(s->last_visits().top + s->last_visits().leaf_points +
                                          s->last_visits().follower_points);
    counters_->leaders.leaders += s->leaders().leaders - lead_before.leaders;
    counters_->leaders.followers += s->leaders().followers - lead_before.followers;
    counters_->leaders.leader_buffer_full += s->leaders().leader_buffer_full - lead_before.leader_buffer_full;
    golden_local_.clear();
    for (const Neighbor& n : found_) {
      k_indices.push_back(map_[n.index]);
      k_sqr_distances.push_back(n.dist2);
      if (settings_.recorder) golden_local_.push_back(n.index);
    }
    return static_cast<int>(found_.size());
  }

  SearchSettings settings_;
  std::shared_ptr<SearchCounters> counters_;
  std::unique_ptr<KdTree> tree_;
  std::vector<pcl::index_t> map_;
  mutable std::map<std::tuple<int, int, float, std::uint32_t>, std::unique_ptr<Searcher>> searchers_;
  mutable std::vector<Neighbor> found_;
  mutable double last_distances_ = 0.0;  // the golden search's distances, for the budget
  // Recording: the tree's serial in the trace, FLANN's input index -> trace index, scratch.
  int serial_ = -1;
  std::vector<int> local_of_;
  mutable std::vector<std::uint32_t> local_, golden_local_;
  mutable double recording_seconds_ = 0.0;  // of the last search, kept out of its search seconds
  // In the loop: the tree's points and build id, the announced queries, the job's answer.
  PointCloud points_;
  std::uint64_t tree_id_ = 0;
  PointCloud expected_;
  mutable std::deque<std::function<void()>> pending_;
  mutable AccelAnswer batch_;
  mutable SearchParams batch_params_;
  mutable bool batch_ran_ = false;
  mutable std::size_t cursor_ = 0;
};

}  // namespace tigris::registration
