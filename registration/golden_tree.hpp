// The golden model behind a plug-in tree (search_plugin.hpp): a two-stage tree of a chosen top
// height over the input cloud's finite points, searched one query at a time, exact or
// approximate, with one searcher (and one leader state) per distinct search. Apart from the
// plug-in because none of it depends on PCL's point type: the template hands over the finite
// points and turns the neighbours (indices into them) into the input cloud's.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <tuple>
#include <vector>

#include "search_counters.hpp"
#include "sw_ref/cloud.hpp"
#include "sw_ref/kdtree.hpp"
#include "sw_ref/search.hpp"

namespace tigris::registration {

// A new id for every plug-in tree build, whatever its point type (the host resends the tree
// image when a job's id differs from the last job's). Single-threaded pipeline.
std::uint64_t next_tree_id();

class GoldenTree {
 public:
  // Builds the tree on `points` (the input's finite points, in index order) at `top_height`,
  // clamped to their full height; no tree when there are none. Every build gets a new id and
  // starts every search's leader state afresh.
  void build(PointCloud points, int top_height);
  // Approximate search starts again with empty Leader Buffers (a new job).
  void forget_leaders() { searchers_.clear(); }

  bool built() const { return tree_ != nullptr; }
  const KdTree& tree() const { return *tree_; }
  const PointCloud& points() const { return points_; }
  std::uint64_t id() const { return id_; }

  // The golden model on the CPU: `q`'s neighbours (indices into points()) in canonical order,
  // valid until the next search; its visits and leaders are counted into `counters` and the
  // distances it computed (its work for the budget) go to `distances`. Needs built().
  const std::vector<Neighbor>& search(const SearchParams& p, const Point3& q, SearchCounters& counters,
                                      double& distances) const;

 private:
  PointCloud points_;
  std::unique_ptr<KdTree> tree_;
  std::uint64_t id_ = 0;
  // Keyed by what tells searches apart in a stage: mode, k, radius, max_nn.
  mutable std::map<std::tuple<int, int, float, std::uint32_t>, std::unique_ptr<Searcher>> searchers_;
  mutable std::vector<Neighbor> found_;
};

}  // namespace tigris::registration
