#include "announced_jobs.hpp"

#include <algorithm>
#include <string>
#include <utility>

namespace tigris::registration {
namespace {

bool same_point(const Point3& a, const Point3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

void count_job(SearchCounters::Accelerated& a, const AccelAnswer& answer, std::size_t queries) {
  ++a.jobs;
  a.queries += queries;
  a.cycles += answer.cycles;
  a.modeled_search_seconds += answer.search_seconds;
  a.modeled_host_seconds += answer.host_seconds;
  a.energy_pj += answer.energy_pj;
  a.visits.top += answer.visits.top;
  a.visits.pruned += answer.visits.pruned;
  a.visits.leaf_visits += answer.visits.leaf_visits;
  a.visits.leaf_points += answer.visits.leaf_points;
  a.visits.follower_points += answer.visits.follower_points;
  a.visits.leader_checks += answer.visits.leader_checks;
}

}  // namespace

void AnnouncedJobs::announce(PointCloud queries) {
  expected_ = std::move(queries);
  ran_ = false;
  cursor_ = 0;
}

void AnnouncedJobs::announce_next() {
  if (!ran_ || cursor_ != expected_.size() || pending_.empty()) return;
  // Off the queue first: the announcement may queue more.
  const std::function<void()> announce = std::move(pending_.front());
  pending_.pop_front();
  announce();
}

namespace {
AccelJob job_of(const PointCloud& queries, const SearchParams& p, const GoldenTree& tree) {
  AccelJob job;
  job.tree_id = tree.id();
  job.points = &tree.points();
  job.top_height = tree.tree().top_height;
  job.queries = &queries;
  job.params = p;
  return job;
}
}  // namespace

void AnnouncedJobs::prefetch(const SearchParams& p, const GoldenTree& tree, AcceleratorPort& port) const {
  if (!expected_.empty() && !ran_ && tree.built()) port.prefetch(job_of(expected_, p, tree));
}

std::optional<JobNeighbors> AnnouncedJobs::serve(const SearchParams& p, const Point3& q, const GoldenTree& tree,
                                                 AcceleratorPort& port, SearchCounters::Accelerated& counters) {
  if (expected_.empty()) return std::nullopt;
  if (!ran_ && same_point(expected_.front(), q)) {
    answer_ = port.run(job_of(expected_, p, tree));
    if (answer_.results.num_queries() != expected_.size())
      throw AcceleratorFailure("the accelerator answered " + std::to_string(answer_.results.num_queries()) +
                               " of a job's " + std::to_string(expected_.size()) + " queries");
    params_ = p;
    ran_ = true;
    cursor_ = 0;
    count_job(counters, answer_, expected_.size());
  }
  if (!ran_ || cursor_ >= expected_.size() || !same_point(expected_[cursor_], q) || !same_search(p, params_))
    return std::nullopt;
  const JobNeighbors served{answer_.results.begin(cursor_), answer_.results.end(cursor_)};
  ++cursor_;
  return served;
}

pcl::Indices AnnouncedJobs::last_job_neighbors(const std::vector<pcl::index_t>& map) const {
  pcl::Indices out;
  out.reserve(answer_.results.neighbors.size());
  for (const Neighbor& n : answer_.results.neighbors) out.push_back(map[n.index]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace tigris::registration
