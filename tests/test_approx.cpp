#include <catch2/catch.hpp>

#include <algorithm>

#include "sw_ref/brute_force.hpp"
#include "sw_ref/search.hpp"
#include "sw_ref/synthetic.hpp"
#include "test_util.hpp"

using namespace tigris;
using namespace tigris::test;

namespace {

SearchParams approx(Mode mode, float thd) {
  SearchParams p;
  p.mode = mode;
  p.k = 5;
  p.radius = 1.0f;
  p.approximate = true;
  p.approx_thd = thd;
  return p;
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
  for (Mode mode : {Mode::NN, Mode::KNN, Mode::Radius}) {
    for (int h : {0, 3, 7}) {
      INFO("mode=" << to_string(mode) << " h=" << h);
      const KdTree tree = build_kdtree(cloud, h);
      SearchParams exact = approx(mode, 0.0f);
      exact.approximate = false;
      const SearchOutput e = search(tree, queries, exact);
      const SearchOutput a = search(tree, queries, approx(mode, 0.0f));
      const auto diff = first_difference(e.results, a.results);
      if (diff) FAIL(*diff);
      CHECK(a.visits.top == e.visits.top);
      CHECK(a.visits.pruned == e.visits.pruned);
      CHECK(a.visits.leaf_points == e.visits.leaf_points);
      CHECK(a.visits.follower_points == 0);
      CHECK(a.leaders.followers == 0);
      CHECK(a.visits.leader_checks > 0);  // leaders are still checked, none is close enough
      CHECK(a.leaders.leaders + a.leaders.leader_buffer_full == a.visits.leaf_visits);
    }
  }
}

TEST_CASE("Algorithm 1 on a hand-built leaf: leader, follower, capacity", "[approx]") {
  // 8 points on a line; h = 0, so the whole cloud is one leaf set.
  PointCloud cloud;
  for (int i = 0; i < 8; ++i) cloud.push_back({static_cast<float>(i), 0, 0});
  const KdTree tree = build_kdtree(cloud, 0);
  const PointCloud queries = {{0.1f, 0, 0}, {0.4f, 0, 0}, {5.2f, 0, 0}, {5.0f, 0, 0}};
  SearchParams p = approx(Mode::KNN, 1.0f);
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
  SearchParams r = approx(Mode::Radius, 1.0f);
  r.radius = 1.5f;
  const SearchOutput rad = search(tree, queries, r);
  CHECK(rad.per_query[1].follower_points == 2);  // q0's in-radius points: 0, 1
  CHECK(rad.results.count(1) == 2);
}

TEST_CASE("approximate search cuts work on the synthetic pair and replays bit for bit", "[approx][synthetic]") {
  const SyntheticPair pair = make_synthetic_pair();
  PointCloud queries(pair.frame1.begin(), pair.frame1.begin() + 20000);
  const KdTree tree = build_kdtree(pair.frame0, 10);
  for (Mode mode : {Mode::NN, Mode::Radius}) {
    SearchParams p;
    p.mode = mode;
    p.radius = 0.30f;
    const SearchOutput exact = search(tree, queries, p);
    p.approximate = true;
    p.approx_thd = default_approx_thd(p);
    const SearchOutput a = search(tree, queries, p);
    INFO("mode " << to_string(mode));
    CHECK(a.leaders.followers > 0);
    CHECK(a.visits.leaf_points + a.visits.follower_points + a.visits.leader_checks <
          exact.visits.leaf_points);
    CHECK(a.schedule.size() == a.visits.leaf_visits);

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
  SearchParams p = approx(Mode::NN, 1.0f);
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
}

TEST_CASE("Searcher, one query at a time, returns what search() returns in the same order", "[approx][searcher]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 2500, 31);
  const PointCloud queries = make_queries(cloud, 300, 31);
  const KdTree tree = build_kdtree(cloud, 6);
  for (bool approximate : {false, true})
    for (Mode mode : {Mode::NN, Mode::KNN, Mode::Radius}) {
      SearchParams p = approx(mode, 1.0f);
      p.approximate = approximate;
      INFO(to_string(mode) << (approximate ? " approximate" : " exact"));
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
