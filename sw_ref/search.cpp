#include "search.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <unordered_map>

namespace tigris {

Mode parse_mode(const std::string& name) {
  if (name == "nn") return Mode::NN;
  if (name == "knn") return Mode::KNN;
  if (name == "radius") return Mode::Radius;
  throw std::invalid_argument("unknown search mode '" + name + "' (use nn, knn or radius)");
}

const char* to_string(Mode mode) {
  switch (mode) {
    case Mode::NN: return "nn";
    case Mode::KNN: return "knn";
    default: return "radius";
  }
}

LeaderScope parse_leader_scope(const std::string& name) {
  if (name == "first_leaf") return LeaderScope::FirstLeaf;
  if (name == "every_leaf") return LeaderScope::EveryLeaf;
  throw std::invalid_argument("unknown leader scope '" + name + "' (use first_leaf or every_leaf)");
}

const char* to_string(LeaderScope scope) { return scope == LeaderScope::FirstLeaf ? "first_leaf" : "every_leaf"; }

LeaderInFlight parse_leader_in_flight(const std::string& name) {
  if (name == "wait") return LeaderInFlight::Wait;
  if (name == "finished_only") return LeaderInFlight::FinishedOnly;
  throw std::invalid_argument("unknown leader in-flight policy '" + name + "' (use wait or finished_only)");
}

const char* to_string(LeaderInFlight policy) { return policy == LeaderInFlight::Wait ? "wait" : "finished_only"; }

float default_approx_thd(const SearchParams& p) { return p.mode == Mode::Radius ? 0.4f * p.radius : 1.2f; }

void validate(const SearchParams& p) {
  if (p.mode == Mode::KNN && p.k < 1) throw std::invalid_argument("k must be >= 1, got " + std::to_string(p.k));
  if (p.mode == Mode::Radius && !(p.radius > 0.0f && std::isfinite(p.radius))) {
    char b[64];
    std::snprintf(b, sizeof b, "radius must be a finite number > 0, got %g", double(p.radius));
    throw std::invalid_argument(b);
  }
  if (p.approximate) {
    if (!(p.approx_thd >= 0.0f && std::isfinite(p.approx_thd)))
      throw std::invalid_argument("approximation threshold must be a finite number >= 0");
    if (p.leader_capacity < 0) throw std::invalid_argument("leader capacity must be >= 0");
    if (p.leader_width < 0) throw std::invalid_argument("leader result width must be >= 0");
    if (p.leader_width != 0 && p.leader_scope == LeaderScope::FirstLeaf)
      throw std::invalid_argument(
          "a leader result width applies to leader scope every_leaf (first_leaf leaders keep "
          "their final results)");
  }
}

void VisitTotals::add(const QueryVisits& v) {
  top += v.top;
  pruned += v.pruned;
  leaf_points += v.leaf_points;
  follower_points += v.follower_points;
  leader_checks += v.leader_checks;
  leaf_visits += v.leaf_visits;
}

namespace {

constexpr std::uint32_t kDone = 0xFFFFFFFFu;
// Small: a query with k in the thousands takes milliseconds (more under the sanitizers), and
// the Python module polls Ctrl-C here; the reporters limit their own rate.
constexpr std::size_t kProgressStep = 64;

// ---- Result collectors: offer() keeps the canonical answer, bound() prunes -------------------

struct NnCollector {
  Neighbor best{kNoPoint, kInfinity};
  explicit NnCollector(const SearchParams&) {}
  float bound() const { return best.dist2; }
  void offer(float d, std::uint32_t i) {
    if (d < best.dist2 || (d == best.dist2 && i < best.index)) best = {i, d};
  }
  void final_list(std::vector<Neighbor>& out) const {
    if (best.index != kNoPoint) out.push_back(best);
  }
  void emit(Results& r) {
    r.append_query(&best, &best + (best.index == kNoPoint ? 0 : 1));
    best = {kNoPoint, kInfinity};
  }
};

struct KnnCollector {
  std::vector<Neighbor> list;  // ascending canonical order, at most k
  std::size_t k;
  explicit KnnCollector(const SearchParams& p) : k(static_cast<std::size_t>(p.k)) { list.reserve(k); }
  float bound() const { return list.size() < k ? kInfinity : list.back().dist2; }
  void offer(float d, std::uint32_t i) { offer_k_best(list, k, Neighbor{i, d}); }
  void final_list(std::vector<Neighbor>& out) const { out.insert(out.end(), list.begin(), list.end()); }
  void emit(Results& r) {
    r.append_query(list.data(), list.data() + list.size());
    list.clear();
  }
};

struct RadiusCollector {
  std::vector<Neighbor> hits;
  float r2;
  std::uint32_t max_nn;
  explicit RadiusCollector(const SearchParams& p) : r2(square(p.radius)), max_nn(p.max_nn) {}
  float bound() const { return r2; }
  void offer(float d, std::uint32_t i) {
    if (d <= r2) hits.push_back({i, d});
  }
  // Every hit, max_nn or not: max_nn only trims what the query returns.
  void final_list(std::vector<Neighbor>& out) const { out.insert(out.end(), hits.begin(), hits.end()); }
  void emit(Results& r) {
    std::sort(hits.begin(), hits.end(), Closer{});
    if (max_nn > 0 && hits.size() > max_nn) hits.resize(max_nn);
    r.append_query(hits.data(), hits.data() + hits.size());
    hits.clear();
  }
};

struct StackEntry {
  std::uint32_t node;
  float plane2;  // squared distance to the split plane that separates this subtree
};

// ---- Leader Buffer state of the approximate search ---------------------------------------------

struct Leader {
  Point3 point;
  std::vector<std::uint32_t> list;  // positions in the tree's leaf arrays
  bool finished = true;             // first_leaf, wait: its list is known
};

constexpr std::uint32_t kNotInLeaf = 0xFFFFFFFFu;

// ---- One query's depth-first search, resumable between leaf visits -----------------------------

template <class Collector>
struct Walker {
  Point3 q;
  StackEntry* stack;
  int sp = 0;
  QueryVisits* visits;
  Collector result;
  std::uint32_t first_leaf = kDone;    // first_leaf scope: the leaf of its Leader Check
  bool leader = false;                 // first_leaf, finished_only: no leader followed: joins when done
  std::uint32_t leader_index = kDone;  // first_leaf, wait: its entry among the leaf's leaders
};

template <class Collector>
class Engine {
 public:
  Engine(const KdTree& tree, const SearchParams& params, SearchOutput& out)
      : t_(tree), p_(params), out_(out), first_leaf_(tree.first_leaf_node()), thd2_(square(params.approx_thd)),
        first_leaf_scope_(params.approximate && params.leader_scope == LeaderScope::FirstLeaf),
        wait_(params.leader_in_flight == LeaderInFlight::Wait) {
    // nonempty_[node] for every heap node down to the leaves: empty ones are never pushed.
    const std::size_t nodes = t_.top.size() + t_.num_leaves();
    nonempty_.resize(nodes);
    for (std::size_t n = 0; n < t_.top.size(); ++n) nonempty_[n] = !t_.top[n].empty();
    for (std::uint32_t j = 0; j < t_.num_leaves(); ++j) nonempty_[first_leaf_ + j] = t_.leaf_size(j) > 0;
    if (p_.approximate) leaders_.resize(t_.num_leaves());
    if (first_leaf_scope_) {  // a leader's final results as positions in the leaf arrays
      std::uint32_t points = 0;
      for (const TopNode& n : t_.top)
        if (!n.empty()) points = std::max(points, n.index + 1);
      for (std::uint32_t i : t_.leaf_index) points = std::max(points, i + 1);
      leaf_position_.assign(points, kNotInLeaf);
      for (std::uint32_t pos = 0; pos < t_.leaf_index.size(); ++pos) leaf_position_[t_.leaf_index[pos]] = pos;
    }
  }

  bool first_leaf_scope() const { return first_leaf_scope_; }
  bool waits() const { return first_leaf_scope_ && wait_; }

  int stack_capacity() const { return std::max(t_.top_height, 1); }

  void start(Walker<Collector>& w) const {
    w.sp = 0;
    w.first_leaf = kDone;
    w.leader = false;
    w.leader_index = kDone;
    if (nonempty_[0]) w.stack[w.sp++] = {0, 0.0f};
  }

  // Walks the top-tree to the query's next non-empty leaf; returns the leaf id or kDone.
  std::uint32_t advance(Walker<Collector>& w) const {
    while (w.sp > 0) {
      const StackEntry e = w.stack[--w.sp];
      if (e.plane2 > w.result.bound()) {
        ++w.visits->pruned;
        continue;
      }
      std::uint32_t node = e.node;
      while (node < first_leaf_) {
        const TopNode& n = t_.top[node];
        ++w.visits->top;
        w.result.offer(dist2(w.q, n.point), n.index);
        const bool left = w.q[n.axis] < n.point[n.axis];
        const std::uint32_t near = 2 * node + (left ? 1 : 2);
        const std::uint32_t far = 2 * node + (left ? 2 : 1);
        if (nonempty_[far]) w.stack[w.sp++] = {far, plane_dist2(w.q, n.point, n.axis)};
        node = nonempty_[near] ? near : kDone;
      }
      if (node != kDone) return node - first_leaf_;
    }
    return kDone;
  }

  void visit_leaf(Walker<Collector>& w, std::uint32_t leaf) {
    ++w.visits->leaf_visits;
    if (!p_.approximate || (first_leaf_scope_ && w.first_leaf != kDone)) {
      scan(w, t_.leaf_begin[leaf], t_.leaf_begin[leaf + 1]);
      return;
    }
    // Paper Algorithm 1: follow the closest leader (order (dist2, arrival)) if within thd.
    std::vector<Leader>& leaders = leaders_[leaf];
    const std::uint32_t closest = closest_leader(w, leaf);
    if (closest != kDone) {
      ++out_.leaders.followers;
      if (first_leaf_scope_) w.sp = 0;  // the authors' code: a follower does not backtrack
      if (leaders[closest].finished)
        follow(w, leaders[closest]);
      else  // its results are complete when the leader's are (only a replay gets here)
        waiting_.emplace(key(leaf, closest), &w);
      return;
    }
    scan(w, t_.leaf_begin[leaf], t_.leaf_begin[leaf + 1]);
    if (first_leaf_scope_) {  // searches on exactly; its list is its final results
      w.first_leaf = leaf;
      if (!wait_) {
        w.leader = true;  // joins when done
      } else if (leaders.size() >= static_cast<std::size_t>(p_.leader_capacity)) {
        ++out_.leaders.leader_buffer_full;
      } else {
        ++out_.leaders.leaders;
        w.leader_index = static_cast<std::uint32_t>(leaders.size());
        leaders.push_back({w.q, {}, false});
      }
      return;
    }
    if (leaders.size() >= static_cast<std::size_t>(p_.leader_capacity)) {
      ++out_.leaders.leader_buffer_full;
      return;
    }
    ++out_.leaders.leaders;
    leaders.push_back({w.q, local_list(w.q, leaf)});
  }

  // The closest of the leaf's leaders (order (dist2, arrival)) if within thd, else kDone.
  std::uint32_t closest_leader(Walker<Collector>& w, std::uint32_t leaf) {
    if (first_leaf_scope_) w.first_leaf = leaf;
    const std::vector<Leader>& leaders = leaders_[leaf];
    std::uint32_t closest = kDone;
    float closest_d = kInfinity;
    for (std::uint32_t i = 0; i < leaders.size(); ++i) {
      const float d = dist2(w.q, leaders[i].point);
      ++w.visits->leader_checks;
      if (closest == kDone || d < closest_d) closest = i, closest_d = d;
    }
    return closest != kDone && closest_d < thd2_ ? closest : kDone;
  }

  void follow(Walker<Collector>& w, const Leader& l) {
    for (std::uint32_t pos : l.list) {
      ++w.visits->follower_points;
      w.result.offer(dist2(w.q, t_.leaf_points[pos]), t_.leaf_index[pos]);
    }
  }

  // A leader's final results that are leaf-set points (the top-tree points on its way down
  // every query to that leaf compares itself), closest first, as leaf-array positions.
  std::vector<std::uint32_t> final_positions(const Walker<Collector>& w) {
    final_.clear();
    w.result.final_list(final_);
    std::sort(final_.begin(), final_.end(), Closer{});
    std::vector<std::uint32_t> list;
    for (const Neighbor& n : final_)
      if (n.index < leaf_position_.size() && leaf_position_[n.index] != kNotInLeaf)
        list.push_back(leaf_position_[n.index]);
    return list;
  }

  // first_leaf: `w`'s search has finished. wait: a leader's list is now known; its waiting
  // followers take it. finished_only: its record goes to its first leaf, which takes it if it
  // has room. Returns whether there was such a record (a finish event): not for a follower, nor
  // for a leader with no leaf-set point among its results.
  bool finish(Walker<Collector>& w) {
    finish_wait(w);
    return finish_join(w);
  }
  void finish_wait(Walker<Collector>& w) {
    if (w.leader_index == kDone) return;
    Leader& l = leaders_[w.first_leaf][w.leader_index];
    const auto waiters = waiting_.equal_range(key(w.first_leaf, w.leader_index));
    w.leader_index = kDone;
    l.list = final_positions(w);
    l.finished = true;
    for (auto it = waiters.first; it != waiters.second; ++it) follow(*it->second, l);
    waiting_.erase(waiters.first, waiters.second);
  }
  bool finish_join(Walker<Collector>& w) {
    if (!w.leader) return false;
    w.leader = false;
    Leader l{w.q, final_positions(w)};
    if (l.list.empty()) return false;
    std::vector<Leader>& leaders = leaders_[w.first_leaf];
    if (leaders.size() >= static_cast<std::size_t>(p_.leader_capacity)) {
      ++out_.leaders.leader_buffer_full;
      return true;
    }
    ++out_.leaders.leaders;
    leaders.push_back(std::move(l));
    return true;
  }

  void scan(Walker<Collector>& w, std::uint32_t first, std::uint32_t last) const {
    w.visits->leaf_points += last - first;
    for (std::uint32_t pos = first; pos < last; ++pos)
      w.result.offer(dist2(w.q, t_.leaf_points[pos]), t_.leaf_index[pos]);
  }

  // A new leader's local result list at `leaf`: its in-radius points (radius) or its R best
  // points of the leaf set (NN/kNN), as positions in the leaf arrays.
  std::vector<std::uint32_t> local_list(const Point3& q, std::uint32_t leaf) const {
    std::vector<Neighbor> cand;  // index field holds the position
    const float r2 = square(p_.radius);
    for (std::uint32_t pos = t_.leaf_begin[leaf]; pos < t_.leaf_begin[leaf + 1]; ++pos) {
      const float d = dist2(q, t_.leaf_points[pos]);
      if (p_.mode != Mode::Radius || d <= r2) cand.push_back({pos, d});
    }
    if (p_.mode != Mode::Radius) {
      // Positions ascend with point index inside a leaf set, so this is (dist2, index) order.
      const std::size_t width = std::min<std::size_t>(cand.size(), p_.effective_leader_width());
      std::partial_sort(cand.begin(), cand.begin() + width, cand.end(), Closer{});
      cand.resize(width);
    }
    std::vector<std::uint32_t> list;
    list.reserve(cand.size());
    for (const Neighbor& c : cand) list.push_back(c.index);
    return list;
  }

  void record(std::uint32_t query, std::uint32_t leaf, ScheduleEntry::Event event = ScheduleEntry::Event::Visit) {
    if (p_.record_schedule) out_.schedule.push_back({query, leaf, event});
  }

 private:
  const KdTree& t_;
  const SearchParams& p_;
  SearchOutput& out_;
  std::uint32_t first_leaf_;
  float thd2_;
  bool first_leaf_scope_, wait_;
  static std::uint64_t key(std::uint32_t leaf, std::uint32_t leader) { return std::uint64_t{leaf} << 32 | leader; }
  std::unordered_multimap<std::uint64_t, Walker<Collector>*>
      waiting_;  // followers of leaders still searching (replays)
  std::vector<std::uint8_t> nonempty_;
  std::vector<std::vector<Leader>> leaders_;
  std::vector<std::uint32_t> leaf_position_;  // first_leaf: point index -> leaf-array position
  std::vector<Neighbor> final_;               // scratch of finish()
};

template <class Collector>
void run_in_order(const KdTree& tree, const PointCloud& queries, const SearchParams& p, SearchOutput& out,
                  const Progress& progress) {
  Engine<Collector> engine(tree, p, out);
  std::vector<StackEntry> stack(engine.stack_capacity());
  Walker<Collector> w{{}, stack.data(), 0, nullptr, Collector(p)};  // emit() resets the result
  for (std::uint32_t q = 0; q < queries.size(); ++q) {
    w.q = queries[q];
    w.visits = &out.per_query[q];
    engine.start(w);
    for (std::uint32_t leaf; (leaf = engine.advance(w)) != kDone;) {
      engine.record(q, leaf);
      engine.visit_leaf(w, leaf);
    }
    const std::uint32_t first_leaf = w.first_leaf;
    if (engine.finish(w)) engine.record(q, first_leaf, ScheduleEntry::Event::Finish);
    w.result.emit(out.results);
    if (progress && (q + 1) % kProgressStep == 0) progress(q + 1, queries.size());
  }
}

template <class Collector>
void run_replay(const KdTree& tree, const PointCloud& queries, const SearchParams& p, const Schedule& schedule,
                SearchOutput& out, const Progress& progress) {
  Engine<Collector> engine(tree, p, out);
  const std::size_t cap = engine.stack_capacity();
  std::vector<StackEntry> stacks(queries.size() * cap);
  std::vector<Walker<Collector>> walkers;
  walkers.reserve(queries.size());
  std::vector<std::uint32_t> pending(queries.size());
  for (std::uint32_t q = 0; q < queries.size(); ++q) {
    walkers.push_back({queries[q], stacks.data() + q * cap, 0, &out.per_query[q], Collector(p)});
    engine.start(walkers[q]);
    pending[q] = engine.advance(walkers[q]);
  }
  for (std::size_t s = 0; s < schedule.size(); ++s) {
    const ScheduleEntry& e = schedule[s];
    const auto row = [&] {  // built only for an error: a frame has hundreds of thousands of rows
      return "schedule row " + std::to_string(s) + " (query " + std::to_string(e.query) + ", leaf " +
             std::to_string(e.leaf) + "): ";
    };
    if (e.query >= queries.size())
      throw ScheduleError(row() + "there are only " + std::to_string(queries.size()) + " queries");
    if (e.event == ScheduleEntry::Event::Finish) {
      Walker<Collector>& w = walkers[e.query];
      if (!engine.first_leaf_scope() || engine.waits())
        throw ScheduleError(row() +
                            "a leader's finish row belongs to approximate search with leader scope first_leaf and "
                            "in-flight policy finished_only");
      if (pending[e.query] != kDone)
        throw ScheduleError(row() + "the query finishes, but its next leaf visit is leaf " +
                            std::to_string(pending[e.query]));
      if (!w.leader)
        throw ScheduleError(row() + "the query is not a leader waiting to join (a follower, or already joined)");
      if (w.first_leaf != e.leaf)
        throw ScheduleError(row() + "the query's first leaf is leaf " + std::to_string(w.first_leaf));
      if (!engine.finish_join(w))
        throw ScheduleError(row() + "the leader found no leaf-set point, so it has no record to join with");
      continue;
    }
    if (pending[e.query] == kDone) throw ScheduleError(row() + "the query has already finished its search");
    if (pending[e.query] != e.leaf)
      throw ScheduleError(row() + "the query's next leaf visit is leaf " + std::to_string(pending[e.query]));
    engine.visit_leaf(walkers[e.query], e.leaf);
    pending[e.query] = engine.advance(walkers[e.query]);
    if (pending[e.query] == kDone) engine.finish_wait(walkers[e.query]);
    if (progress && (s + 1) % kProgressStep == 0) progress(s + 1, schedule.size());
  }
  for (std::uint32_t q = 0; q < queries.size(); ++q)
    if (pending[q] != kDone)
      throw ScheduleError("the schedule ends but query " + std::to_string(q) + " still has to visit leaf " +
                          std::to_string(pending[q]));
  for (auto& w : walkers) w.result.emit(out.results);
  out.schedule = schedule;
}

template <class Collector>
void run(const KdTree& tree, const PointCloud& queries, const SearchParams& p, const Schedule* replay,
         SearchOutput& out, const Progress& progress) {
  if (replay)
    run_replay<Collector>(tree, queries, p, *replay, out, progress);
  else
    run_in_order<Collector>(tree, queries, p, out, progress);
}

}  // namespace

struct Searcher::Impl {
  virtual ~Impl() = default;
  virtual void search(const Point3& q, std::vector<Neighbor>& out) = 0;
  SearchOutput totals;  // visits and leaders summed over calls (no results, no schedule)
  QueryVisits last;     // the last call's visits
  std::uint64_t queries = 0;
};

namespace {

template <class Collector>
struct SearcherImpl final : Searcher::Impl {
  SearchParams params;  // owned: the engine keeps a reference
  Engine<Collector> engine;
  std::vector<StackEntry> stack;
  Walker<Collector> walker;
  Results one;

  SearcherImpl(const KdTree& tree, const SearchParams& p)
      : params(p), engine(tree, params, totals),
        stack(engine.stack_capacity()), walker{{}, stack.data(), 0, &last, Collector(params)} {}

  void search(const Point3& q, std::vector<Neighbor>& out) override {
    walker.q = q;
    last = {};
    engine.start(walker);
    for (std::uint32_t leaf; (leaf = engine.advance(walker)) != kDone;) engine.visit_leaf(walker, leaf);
    engine.finish(walker);
    one = Results{};
    walker.result.emit(one);
    out.assign(one.begin(0), one.end(0));
    totals.visits.add(last);
    ++queries;
  }
};

}  // namespace

Searcher::Searcher(const KdTree& tree, const SearchParams& params) {
  validate(params);
  SearchParams p = params;
  p.record_schedule = false;
  switch (p.mode) {
    case Mode::NN: impl_ = std::make_unique<SearcherImpl<NnCollector>>(tree, p); break;
    case Mode::KNN: impl_ = std::make_unique<SearcherImpl<KnnCollector>>(tree, p); break;
    case Mode::Radius: impl_ = std::make_unique<SearcherImpl<RadiusCollector>>(tree, p); break;
  }
}

Searcher::~Searcher() = default;
void Searcher::search(const Point3& q, std::vector<Neighbor>& out) { impl_->search(q, out); }
const VisitTotals& Searcher::visits() const { return impl_->totals.visits; }
const LeaderTotals& Searcher::leaders() const { return impl_->totals.leaders; }
const QueryVisits& Searcher::last_visits() const { return impl_->last; }
std::uint64_t Searcher::queries() const { return impl_->queries; }

SearchOutput search(const KdTree& tree, const PointCloud& queries, const SearchParams& params, const Schedule* replay,
                    const Progress& progress) {
  validate(params);
  validate_cloud(queries, "queries");
  if (queries.size() >= kNoPoint) throw std::invalid_argument("too many queries");
  SearchOutput out;
  out.per_query.resize(queries.size());
  out.results.offset.reserve(queries.size() + 1);
  switch (params.mode) {
    case Mode::NN: run<NnCollector>(tree, queries, params, replay, out, progress); break;
    case Mode::KNN: run<KnnCollector>(tree, queries, params, replay, out, progress); break;
    case Mode::Radius: run<RadiusCollector>(tree, queries, params, replay, out, progress); break;
  }
  for (const QueryVisits& v : out.per_query) out.visits.add(v);
  return out;
}

}  // namespace tigris
