#include "golden_tree.hpp"

#include <algorithm>
#include <utility>

namespace tigris::registration {

std::uint64_t next_tree_id() {
  static std::uint64_t id = 0;
  return ++id;
}

void GoldenTree::build(PointCloud points, int top_height) {
  searchers_.clear();  // they refer to the old tree
  points_ = std::move(points);
  tree_.reset();
  id_ = next_tree_id();
  if (points_.empty()) return;
  const int height = std::min(top_height, full_height_for(points_.size()));
  tree_ = std::make_unique<KdTree>(build_kdtree(points_, height));
}

const std::vector<Neighbor>& GoldenTree::search(const SearchParams& p, const Point3& q, SearchCounters& counters,
                                                double& distances) const {
  auto& s = searchers_[std::make_tuple(static_cast<int>(p.mode), p.k, p.radius, p.max_nn)];
  if (!s) s = std::make_unique<Searcher>(*tree_, p);
  const LeaderTotals lead_before = s->leaders();
  s->search(q, found_);
  distances = count_golden_search(counters, s->last_visits(), lead_before, s->leaders());
  return found_;
}

}  // namespace tigris::registration
