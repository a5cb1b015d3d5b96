#include <catch2/catch.hpp>

#include <algorithm>

#include "sw_ref/brute_force.hpp"
#include "sw_ref/search.hpp"
#include "test_util.hpp"
#include "workloads/synthetic.hpp"

using namespace tigris;
using namespace tigris::test;

namespace {

// The three readings of Algorithm 1 (docs/model.md): first_leaf with wait (the default),
// first_leaf with finished_only, every_leaf.
struct Variant {
  const char* name;
  LeaderScope scope;
  LeaderInFlight in_flight;
};
const Variant kVariants[] = {{"first_leaf/wait", LeaderScope::FirstLeaf, LeaderInFlight::Wait},
                             {"first_leaf/finished_only", LeaderScope::FirstLeaf, LeaderInFlight::FinishedOnly},
                             {"every_leaf", LeaderScope::EveryLeaf, LeaderInFlight::Wait}};

SearchParams approx(Mode mode, float thd, const Variant& v = kVariants[0]) {
  SearchParams p;
  p.mode = mode;
  p.k = 5;
  p.radius = 1.0f;
  p.approximate = true;
  p.approx_thd = thd;
  p.leader_scope = v.scope;
  p.leader_in_flight = v.in_flight;
  return p;
}

// Queries that reach a leaf: each makes one Leader Check under first_leaf.
std::uint64_t checked(const SearchOutput& o) {
  return static_cast<std::uint64_t>(
      std::count_if(o.per_query.begin(), o.per_query.end(), [](const QueryVisits& v) { return v.leaf_visits > 0; }));
}

std::size_t visit_rows(const Schedule& s) {
  return static_cast<std::size_t>(
      std::count_if(s.begin(), s.end(), [](const ScheduleEntry& e) { return e.event == ScheduleEntry::Event::Visit; }));
}

void require_same(const SearchOutput& a, const SearchOutput& b) {
  const auto diff = first_difference(a.results, b.results);
  if (diff) FAIL(*diff);
  REQUIRE(a.visits.top == b.visits.top);
  REQUIRE(a.visits.pruned == b.visits.pruned);
  REQUIRE(a.visits.leaf_points == b.visits.leaf_points);
  REQUIRE(a.visits.follower_points == b.visits.follower_points);
  REQUIRE(a.visits.leader_checks == b.visits.leader_checks);
  REQUIRE(a.leaders.leaders == b.leaders.leaders);
  REQUIRE(a.leaders.followers == b.leaders.followers);
}

}  // namespace

TEST_CASE("approximate search with threshold 0 equals exact search", "[approx]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 4000, 21);
  const PointCloud queries = make_queries(cloud, 600, 21);
  for (const Variant& variant : kVariants)
    for (Mode mode : {Mode::NN, Mode::KNN, Mode::Radius}) {
      for (int h : {0, 3, 7}) {
        INFO(variant.name << " mode=" << to_string(mode) << " h=" << h);
        const KdTree tree = build_kdtree(cloud, h);
        SearchParams exact = approx(mode, 0.0f);
        exact.approximate = false;
        const SearchOutput e = search(tree, queries, exact);
        const SearchOutput a = search(tree, queries, approx(mode, 0.0f, variant));
        const auto diff = first_difference(e.results, a.results);
        if (diff) FAIL(*diff);
        CHECK(a.visits.top == e.visits.top);
        CHECK(a.visits.pruned == e.visits.pruned);
        CHECK(a.visits.leaf_points == e.visits.leaf_points);
        CHECK(a.visits.follower_points == 0);
        CHECK(a.leaders.followers == 0);
        CHECK(a.visits.leader_checks > 0);            // leaders are still checked, none is close enough
        if (variant.scope == LeaderScope::EveryLeaf)  // every leaf visit is a check
          CHECK(a.leaders.leaders + a.leaders.leader_buffer_full == a.visits.leaf_visits);
        else if (variant.in_flight == LeaderInFlight::Wait)  // one check per query, at its first leaf
          CHECK(a.leaders.leaders + a.leaders.leader_buffer_full == checked(a));
        else  // finished_only: a leader with no leaf-set point among its results has no record
          CHECK(a.leaders.leaders + a.leaders.leader_buffer_full <= checked(a));
      }
    }
}

TEST_CASE("Algorithm 1 on a hand-built leaf: leader, follower, capacity", "[approx]") {
  // 8 points on a line; h = 0, so the whole cloud is one leaf set.
  PointCloud cloud;
  for (int i = 0; i < 8; ++i) cloud.push_back({static_cast<float>(i), 0, 0});
  const KdTree tree = build_kdtree(cloud, 0);
  const PointCloud queries = {{0.1f, 0, 0}, {0.4f, 0, 0}, {5.2f, 0, 0}, {5.0f, 0, 0}};
  SearchParams p = approx(Mode::KNN, 1.0f, kVariants[2]);
  p.k = 2;  // R = k = 2
  const SearchOutput out = search(tree, queries, p);
  // q0 leads (R best: 0, 1); q1 is 0.3 from q0 and follows: sees only points 0 and 1;
  // q2 is 5.1 from q0 and leads (best 5, 6); q3 is 0.2 from q2 and follows q2.
  CHECK(out.leaders.leaders == 2);
  CHECK(out.leaders.followers == 2);
  CHECK(out.per_query[0].leaf_points == 8);
  CHECK(out.per_query[1].leaf_points == 0);
  CHECK(out.per_query[1].follower_points == 2);
  CHECK(out.per_query[1].leader_checks == 1);
  CHECK(out.per_query[2].leader_checks == 1);
  CHECK(out.per_query[3].leader_checks == 2);
  CHECK(out.results.begin(1)[0].index == 0);
  CHECK(out.results.begin(1)[1].index == 1);
  CHECK(out.results.begin(3)[0].index == 5);
  CHECK(out.results.begin(3)[1].index == 6);

  // Capacity 1: q2 must scan exactly but cannot join the Leader Buffer; q3 then follows q0?
  // No: q0 is 4.9 away, beyond thd, so q3 scans exactly too.
  p.leader_capacity = 1;
  const SearchOutput capped = search(tree, queries, p);
  CHECK(capped.leaders.leaders == 1);
  CHECK(capped.leaders.followers == 1);
  CHECK(capped.leaders.leader_buffer_full == 2);
  CHECK(capped.per_query[3].leaf_points == 8);
  CHECK(capped.results.begin(3)[0].index == 5);
  CHECK(capped.results.begin(3)[1].index == 4);  // 5.0: dist 0 to 5, 1 to 4 and 6; index 4 first

  // Radius: a leader's list holds its in-radius points; the follower keeps its own in-radius ones.
  SearchParams r = approx(Mode::Radius, 1.0f, kVariants[2]);
  r.radius = 1.5f;
  const SearchOutput rad = search(tree, queries, r);
  CHECK(rad.per_query[1].follower_points == 2);  // q0's in-radius points: 0, 1
  CHECK(rad.results.count(1) == 2);
}

TEST_CASE("first_leaf, the authors' code: a follower takes its leader's final results and stops", "[approx]") {
  // The hand-built leaf of the test above, searched as the authors' code does. h = 0: every
  // result is a leaf-set point, so a leader's list is its whole final result.
  PointCloud cloud;
  for (int i = 0; i < 8; ++i) cloud.push_back({static_cast<float>(i), 0, 0});
  const KdTree tree = build_kdtree(cloud, 0);
  const PointCloud queries = {{0.1f, 0, 0}, {0.4f, 0, 0}, {5.2f, 0, 0}, {5.0f, 0, 0}};
  for (const Variant& v : {kVariants[0], kVariants[1]}) {
    INFO(v.name);
    SearchParams p = approx(Mode::KNN, 1.0f, v);
    p.k = 2;
    const SearchOutput out = search(tree, queries, p);
    // q0 leads, finds 0, 1; q1 follows it; q2 leads (5, 6); q3 follows q2 and gets 5, 6 where
    // exact search has 5, 4 (4 and 6 tie at 1 m: the smaller index).
    CHECK(out.leaders.leaders == 2);
    CHECK(out.leaders.followers == 2);
    CHECK(out.per_query[1].follower_points == 2);
    CHECK(out.per_query[3].leader_checks == 2);
    CHECK(out.results.begin(3)[0].index == 5);
    CHECK(out.results.begin(3)[1].index == 6);
    // In index order a leader has finished before the next query checks: both policies agree.
    CHECK(out.schedule.size() == (v.in_flight == LeaderInFlight::Wait ? 4 : 6));  // + 2 finish rows
  }

  // A follower does not backtrack: on a tree (h = 2) a query just across a split plane from
  // its leader's points visits one leaf and returns its leader's nearest, not its own.
  PointCloud line;
  for (int i = 0; i < 64; ++i) line.push_back({static_cast<float>(i) * 0.1f, 0, 0});
  const KdTree t2 = build_kdtree(line, 2);
  const PointCloud q2 = {{1.52f, 0, 0}, {1.55f, 0, 0}};
  SearchParams nn = approx(Mode::NN, 1.0f);
  const SearchOutput a = search(t2, q2, nn);
  nn.approximate = false;
  const SearchOutput e = search(t2, q2, nn);
  CHECK(a.leaders.followers == 1);
  CHECK(a.per_query[1].leaf_visits == 1);
  CHECK(a.per_query[1].follower_points <= 1);
  CHECK(a.per_query[1].leaf_visits <= e.per_query[1].leaf_visits);
}

TEST_CASE("first_leaf: a replay in another order of whole queries changes the leaders, legally", "[approx]") {
  // The order of the first-leaf checks decides who leads. (Followers that check while their
  // leader still searches, which only the accelerator's interleaving produces, are replayed in
  // test_hw_approx.cpp.)
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 3000, 9);
  const PointCloud queries = make_queries(cloud, 400, 9);
  const KdTree tree = build_kdtree(cloud, 5);
  for (Mode mode : {Mode::NN, Mode::KNN, Mode::Radius}) {
    INFO(to_string(mode));
    const SearchParams p = approx(mode, 1.5f);
    const SearchOutput in_order = search(tree, queries, p);
    std::vector<Schedule> per_query(queries.size());
    for (const ScheduleEntry& e : in_order.schedule) per_query[e.query].push_back(e);
    // Only the first visits, last query first: the leaders' later visits are missing.
    Schedule firsts;
    for (std::size_t q = queries.size(); q-- > 0;)
      if (!per_query[q].empty()) firsts.push_back(per_query[q].front());
    CHECK_THROWS_WITH(search(tree, queries, p, &firsts), Catch::Contains("still has to visit leaf"));
    // Whole queries, last first: legal while every query keeps its role, else the replay names
    // the row whose visit the query's traversal does not expect.
    Schedule reversed;
    for (std::size_t q = queries.size(); q-- > 0;)
      reversed.insert(reversed.end(), per_query[q].begin(), per_query[q].end());
    try {
      const SearchOutput r = search(tree, queries, p, &reversed);
      CHECK(r.leaders.leaders + r.leaders.followers + r.leaders.leader_buffer_full == checked(r));
    } catch (const ScheduleError& e) {
      CHECK_THAT(e.what(), Catch::Contains("schedule row"));
    }
  }
}

TEST_CASE("approximate search cuts work on the synthetic pair and replays bit for bit", "[approx][synthetic]") {
  const SyntheticPair pair = make_synthetic_pair();
  PointCloud queries(pair.frame1.begin(), pair.frame1.begin() + 20000);
  const KdTree tree = build_kdtree(pair.frame0, 10);
  for (const Variant& variant : kVariants)
    for (Mode mode : {Mode::NN, Mode::Radius}) {
      SearchParams p;
      p.mode = mode;
      p.radius = 0.30f;
      const SearchOutput exact = search(tree, queries, p);
      p.approximate = true;
      p.approx_thd = default_approx_thd(p);
      p.leader_scope = variant.scope;
      p.leader_in_flight = variant.in_flight;
      const SearchOutput a = search(tree, queries, p);
      INFO(variant.name << " mode " << to_string(mode));
      CHECK(a.leaders.followers > 0);
      CHECK(a.visits.leaf_points + a.visits.follower_points + a.visits.leader_checks < exact.visits.leaf_points);
      CHECK(visit_rows(a.schedule) == a.visits.leaf_visits);

      // Replaying the recorded schedule reproduces everything.
      const SearchOutput replay = search(tree, queries, p, &a.schedule);
      require_same(a, replay);

      // Another order of the same exact-search visits: round-robin over queries (last first),
      // one leaf visit each. Exact search has no order dependence, so nothing may change.
      // (With leaders, a query's later leaf visits depend on the order, so a recorded schedule
      // is only valid in its own order; the hardware records its own.)
      std::vector<Schedule> per_query(queries.size());
      for (const ScheduleEntry& e : exact.schedule) per_query[e.query].push_back(e);
      Schedule interleaved;
      for (std::size_t round = 0; interleaved.size() < exact.schedule.size(); ++round)
        for (std::size_t q = queries.size(); q-- > 0;)
          if (round < per_query[q].size()) interleaved.push_back(per_query[q][round]);
      SearchParams e = p;
      e.approximate = false;
      const SearchOutput exact_replay = search(tree, queries, e, &interleaved);
      require_same(exact, exact_replay);
      CHECK(exact_replay.schedule == interleaved);
      CHECK_FALSE(interleaved == exact.schedule);
    }
}

TEST_CASE("a schedule that does not match the traversal is an error, not a silent skip", "[approx]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 2000, 8);
  const PointCloud queries = make_queries(cloud, 50, 8);
  const KdTree tree = build_kdtree(cloud, 5);
  SearchParams p = approx(Mode::NN, 1.0f, kVariants[2]);
  const SearchOutput out = search(tree, queries, p);
  REQUIRE(out.schedule.size() > 2);

  Schedule wrong_leaf = out.schedule;
  wrong_leaf[1].leaf ^= 1;
  CHECK_THROWS_WITH(search(tree, queries, p, &wrong_leaf), Catch::Contains("schedule row 1"));
  Schedule missing = out.schedule;
  missing.pop_back();
  CHECK_THROWS_WITH(search(tree, queries, p, &missing), Catch::Contains("still has to visit leaf"));
  Schedule extra = out.schedule;
  extra.push_back(out.schedule.back());
  CHECK_THROWS_WITH(search(tree, queries, p, &extra), Catch::Contains("already finished"));
  Schedule bad_query = out.schedule;
  bad_query[0].query = 50;
  CHECK_THROWS_AS(search(tree, queries, p, &bad_query), ScheduleError);

  // Finish rows (first_leaf, finished_only) must be where the leader's search has ended.
  using Event = ScheduleEntry::Event;
  SearchParams f = approx(Mode::NN, 1.0f, kVariants[1]);
  const SearchOutput fo = search(tree, queries, f);
  const auto finish = std::find_if(fo.schedule.begin(), fo.schedule.end(),
                                   [](const ScheduleEntry& e) { return e.event == Event::Finish; });
  REQUIRE(finish != fo.schedule.end());
  const std::size_t at = static_cast<std::size_t>(finish - fo.schedule.begin());
  REQUIRE(at > 0);
  std::size_t last = at;  // the leader's last visit
  while (fo.schedule[--last].query != fo.schedule[at].query) {
  }
  Schedule early = fo.schedule;  // the finish just before it
  early.erase(early.begin() + static_cast<std::ptrdiff_t>(at));
  early.insert(early.begin() + static_cast<std::ptrdiff_t>(last), fo.schedule[at]);
  CHECK_THROWS_WITH(search(tree, queries, f, &early), Catch::Contains("its next leaf visit"));
  Schedule wrong = fo.schedule;
  wrong[at].leaf ^= 1;
  CHECK_THROWS_WITH(search(tree, queries, f, &wrong), Catch::Contains("first leaf is leaf"));
  Schedule twice = fo.schedule;
  twice.insert(twice.begin() + static_cast<std::ptrdiff_t>(at) + 1, fo.schedule[at]);
  CHECK_THROWS_WITH(search(tree, queries, f, &twice), Catch::Contains("not a leader waiting to join"));
  // A finish row means nothing to the other readings.
  CHECK_THROWS_WITH(search(tree, queries, approx(Mode::NN, 1.0f), &fo.schedule), Catch::Contains("finished_only"));
  // Without the finish rows nobody joins, so the in-order followers search on: their visits
  // are missing, and the replay says so.
  Schedule no_finish;
  for (const ScheduleEntry& e : fo.schedule)
    if (e.event == Event::Visit) no_finish.push_back(e);
  CHECK_THROWS_WITH(search(tree, queries, f, &no_finish), Catch::Contains("schedule"));
}

TEST_CASE("Searcher, one query at a time, returns what search() returns in the same order", "[approx][searcher]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 2500, 31);
  const PointCloud queries = make_queries(cloud, 300, 31);
  const KdTree tree = build_kdtree(cloud, 6);
  for (const Variant& variant : kVariants)
    for (bool approximate : {false, true})
      for (Mode mode : {Mode::NN, Mode::KNN, Mode::Radius}) {
        SearchParams p = approx(mode, 1.0f, variant);
        p.approximate = approximate;
        INFO(variant.name << " " << to_string(mode) << (approximate ? " approximate" : " exact"));
        const SearchOutput batch = search(tree, queries, p);
        Searcher one(tree, p);
        Results got;
        std::vector<Neighbor> n;
        for (const Point3& q : queries) {
          one.search(q, n);
          got.append_query(n.data(), n.data() + n.size());
        }
        const auto diff = first_difference(batch.results, got);
        if (diff) FAIL(*diff);
        CHECK(one.queries() == queries.size());
        CHECK(one.visits().top == batch.visits.top);
        CHECK(one.visits().leaf_points == batch.visits.leaf_points);
        CHECK(one.visits().follower_points == batch.visits.follower_points);
        CHECK(one.visits().leader_checks == batch.visits.leader_checks);
        CHECK(one.leaders().followers == batch.leaders.followers);
        CHECK(one.leaders().leaders == batch.leaders.leaders);
        if (approximate) CHECK(one.leaders().followers > 0);
      }
}
