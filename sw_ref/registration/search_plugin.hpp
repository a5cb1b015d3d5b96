// The PCL search plug-in (DESIGN.md section 15): a pcl::search::KdTree<PointT> subclass, so
// PCL's NormalEstimation, FPFH/SHOT estimation, CorrespondenceEstimation and
// IterativeClosestPoint accept it unchanged, that answers every search from the golden model
// (exact, or approximate leader/follower search, on a two-stage tree of a chosen top height) or,
// as the CPU baseline, from PCL's own KdTreeFLANN. It never builds a FLANN index unless asked
// for the baseline. Every search is counted (and timed) into the counters of its stage.
//
// Approximate search keeps leader state between calls (mutable behind PCL's const search
// methods): results depend on the order of the calls, so never use it from PCL's OMP classes.
#pragma once

#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <pcl/search/kdtree.h>

#include "sw_ref/kdtree.hpp"
#include "sw_ref/search.hpp"

namespace tigris::registration {

enum class Backend { Flann, Exact, Approx };
Backend parse_backend(const std::string& name);  // "flann" | "exact" | "approx"
const char* to_string(Backend backend);

struct SearchSettings {
  Backend backend = Backend::Exact;
  int top_height = 10;          // clamped to each cloud's full height
  float nn_thd = 1.2f;          // approximate NN/kNN: follow a leader this close (metres)
  float radius_thd = 0.4f;      // approximate radius: threshold as a fraction of r
  int leader_capacity = 16;
  int leader_width = 0;         // R for NN/kNN (0: k)
};

// What one pipeline stage's searches cost. `searches` counts query points searched (PCL's
// batch calls loop over single ones), `builds` the trees built (one per input cloud set).
struct SearchCounters {
  std::uint64_t searches = 0, neighbors = 0, builds = 0;
  double search_seconds = 0.0, build_seconds = 0.0;
  VisitTotals visits;    // golden back-ends only
  LeaderTotals leaders;  // approximate only
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
      : Base(true), settings_(settings), counters_(std::move(counters)) {}

  // The counters searches are charged to (the pipeline switches them per stage).
  void set_counters(std::shared_ptr<SearchCounters> counters) { counters_ = std::move(counters); }
  const std::shared_ptr<SearchCounters>& counters() const { return counters_; }

  void setInputCloud(const PointCloudConstPtr& cloud, const IndicesConstPtr& indices = IndicesConstPtr()) override {
    const auto t0 = Clock::now();
    if (settings_.backend == Backend::Flann) {
      Base::setInputCloud(cloud, indices);
    } else {
      this->input_ = cloud;
      this->indices_ = indices;
      build_golden();
    }
    ++counters_->builds;
    counters_->build_seconds += seconds_since(t0);
  }

  int nearestKSearch(const PointT& point, int k, pcl::Indices& k_indices,
                     std::vector<float>& k_sqr_distances) const override {
    const auto t0 = Clock::now();
    int n;
    if (settings_.backend == Backend::Flann) {
      n = Base::nearestKSearch(point, k, k_indices, k_sqr_distances);
    } else {
      SearchParams p;
      p.mode = k == 1 ? Mode::NN : Mode::KNN;
      p.k = k;
      n = golden(p, point, k_indices, k_sqr_distances);
    }
    charge(n, t0);
    return n;
  }

  int radiusSearch(const PointT& point, double radius, pcl::Indices& k_indices,
                   std::vector<float>& k_sqr_distances, unsigned int max_nn = 0) const override {
    const auto t0 = Clock::now();
    int n;
    if (settings_.backend == Backend::Flann) {
      n = Base::radiusSearch(point, radius, k_indices, k_sqr_distances, max_nn);
    } else {
      SearchParams p;
      p.mode = Mode::Radius;
      p.radius = static_cast<float>(radius);
      p.max_nn = max_nn;
      n = golden(p, point, k_indices, k_sqr_distances);
    }
    charge(n, t0);
    return n;
  }

 private:
  static double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
  }
  void charge(int n, Clock::time_point t0) const {
    ++counters_->searches;
    counters_->neighbors += static_cast<std::uint64_t>(n > 0 ? n : 0);
    counters_->search_seconds += seconds_since(t0);
  }

  // The golden tree over the finite points of the input (PCL's FLANN skips the others too);
  // map_ takes a golden point index back to the input cloud's.
  void build_golden() {
    searchers_.clear();
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
    tree_.reset();
    if (pts.empty()) return;
    const int height = std::min(settings_.top_height, full_height_for(pts.size()));
    tree_ = std::make_unique<KdTree>(build_kdtree(pts, height));
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
    }
    // One Searcher (and one leader state) per distinct search: mode, k, radius, max_nn.
    auto& s = searchers_[std::make_tuple(static_cast<int>(p.mode), p.k, p.radius, p.max_nn)];
    if (!s) s = std::make_unique<Searcher>(*tree_, p);
    const VisitTotals before = s->visits();
    const LeaderTotals lead_before = s->leaders();
    s->search({point.x, point.y, point.z}, found_);
    add_difference(counters_->visits, before, s->visits());
    counters_->leaders.leaders += s->leaders().leaders - lead_before.leaders;
    counters_->leaders.followers += s->leaders().followers - lead_before.followers;
    counters_->leaders.leader_buffer_full += s->leaders().leader_buffer_full - lead_before.leader_buffer_full;
    for (const Neighbor& n : found_) {
      k_indices.push_back(map_[n.index]);
      k_sqr_distances.push_back(n.dist2);
    }
    return static_cast<int>(found_.size());
  }

  static void add_difference(VisitTotals& to, const VisitTotals& a, const VisitTotals& b) {
    to.top += b.top - a.top;
    to.pruned += b.pruned - a.pruned;
    to.leaf_points += b.leaf_points - a.leaf_points;
    to.follower_points += b.follower_points - a.follower_points;
    to.leader_checks += b.leader_checks - a.leader_checks;
    to.leaf_visits += b.leaf_visits - a.leaf_visits;
  }

  SearchSettings settings_;
  std::shared_ptr<SearchCounters> counters_;
  std::unique_ptr<KdTree> tree_;
  std::vector<pcl::index_t> map_;
  mutable std::map<std::tuple<int, int, float, std::uint32_t>, std::unique_ptr<Searcher>> searchers_;
  mutable std::vector<Neighbor> found_;
};

}  // namespace tigris::registration
