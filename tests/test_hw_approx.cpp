// Approximate (leader/follower) search on the accelerator (docs/model.md): bit-exact
// against the golden model's replay of the accelerator's own schedule across machines, issue
// policies and Leader Buffer capacities; thd 0 equals exact search; the Leader Check's cost.
#include <catch2/catch.hpp>

#include <cmath>

#include "hw_cases.hpp"
#include "test_util.hpp"
#include "workloads/synthetic.hpp"

using namespace tigris;
using namespace tigris::test;

namespace {

hw::AcceleratorConfig with_capacity(hw::AcceleratorConfig c, int capacity, bool mqmn = false) {
  c.leader.capacity_per_leaf = capacity;
  if (mqmn) c.be.issue_policy = "mqmn";
  return c;
}

// The readings of Algorithm 1 (docs/model.md): first_leaf/wait (the default), first_leaf/
// finished_only, every_leaf.
SearchParams reading(SearchParams p, const std::string& name) {
  if (name == "every_leaf") p.leader_scope = LeaderScope::EveryLeaf;
  if (name == "finished_only") p.leader_in_flight = LeaderInFlight::FinishedOnly;
  return p;
}
const char* const kReadings[] = {"wait", "finished_only", "every_leaf"};

// Queries that reach a leaf: under first_leaf each makes one Leader Check.
std::uint64_t checked(const SimOutcome& o) {
  std::uint64_t n = 0;
  for (const QueryVisits& v : o.visits.per_query) n += v.leaf_visits > 0;
  return n;
}

std::uint64_t leaders(const SimOutcome& o) { return o.visits.leaders.leaders; }
std::uint64_t followers(const SimOutcome& o) { return o.visits.leaders.followers; }
std::uint64_t full(const SimOutcome& o) { return o.visits.leaders.leader_buffer_full; }

}  // namespace

TEST_CASE("approximate search is bit-exact with schedule replay: machines, policies, capacities", "[hw][approx]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 3000, 21);
  const PointCloud queries = make_queries(cloud, 400, 21);
  const std::vector<std::pair<std::string, SearchParams>> modes = {
      {"nn", approximate(mode(Mode::NN), 1.2f)},
      {"knn5", approximate(mode(Mode::KNN, 5), 1.2f)},
      {"knn5 R2",
       [] {
         auto p = approximate(mode(Mode::KNN, 5), 1.0f);
         p.leader_width = 2;
         return p;
       }()},
      {"r1.0", approximate(mode(Mode::Radius, 1, 1.0f), 0.4f)},
      {"r1.5 max_nn 3", approximate(mode(Mode::Radius, 1, 1.5f, 3), 0.6f)}};
  std::vector<Case> cases;
  std::vector<std::string> readings;
  for (const char* r : kReadings)
    for (const auto& [name, p] : modes) {
      if (p.leader_width > 0 && std::string(r) != "every_leaf") continue;  // R is every_leaf's
      for (const auto& [machine, c] : std::vector<std::pair<std::string, hw::AcceleratorConfig>>{
               {"1/1/1", units(1, 1, 1, 5)}, {"4/3/5", units(4, 3, 5, 5)}, {"64/32/32", units(64, 32, 32, 5)}})
        for (int capacity : {1, 16})
          for (bool mqmn : {false, true}) {
            cases.push_back({std::string(r) + " " + name + " " + machine + " cap" + std::to_string(capacity) +
                                 (mqmn ? " mqmn" : " mqsn"),
                             with_capacity(c, capacity, mqmn), reading(p, r)});
            readings.push_back(r);
          }
    }
  const auto out = run_and_check(cloud, queries, cases);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    INFO(cases[i].name);
    const SimOutcome& o = out[i];
    // Every path is taken: leaders, followers (finished_only on a large machine may have none:
    // its queries are all in flight at once), and with capacity 1 a full Leader Buffer.
    CHECK(leaders(o) > 0);
    if (readings[i] != "finished_only") CHECK(followers(o) > 0);
    if (cases[i].config.leader.capacity_per_leaf == 1 && readings[i] != "finished_only") CHECK(full(o) > 0);
    if (readings[i] == "every_leaf")  // a check at every leaf visit
      CHECK(leaders(o) + followers(o) + full(o) == o.visits.visits.leaf_visits);
    else if (readings[i] == "wait")  // one check per query, at its first leaf
      CHECK(leaders(o) + followers(o) + full(o) == checked(o));
    else  // finished_only: a leader whose results hold no leaf-set point sends no record
      CHECK(leaders(o) + followers(o) + full(o) <= checked(o));
    CHECK(o.units["search_units"]["leader_check"]["followers"].get<std::uint64_t>() == followers(o));
    if (readings[i] != "every_leaf")  // a follower does not backtrack: one leaf visit
      for (const QueryVisits& v : o.visits.per_query)
        if (v.follower_points > 0) REQUIRE(v.leaf_visits == 1);
  }
}

TEST_CASE("approximate search with thd 0 returns the exact results and visits", "[hw][approx]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 2500, 22);
  const PointCloud queries = make_queries(cloud, 300, 22);
  std::vector<Case> cases;
  const std::vector<SearchParams> exact = {mode(Mode::NN), mode(Mode::KNN, 4), mode(Mode::Radius, 1, 1.0f)};
  for (const char* r : kReadings)
    for (const SearchParams& p : exact)
      cases.push_back(
          {std::string(r) + " " + to_string(p.mode) + " thd 0", units(8, 4, 8, 6), reading(approximate(p, 0.0f), r)});
  const auto out = run_and_check(cloud, queries, cases);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    INFO(cases[i].name);
    const KdTree tree = build_kdtree(cloud, 6);
    const SearchOutput golden = search(tree, queries, exact[i % exact.size()]);
    CHECK_FALSE(first_difference(golden.results, out[i].results));
    CHECK(followers(out[i]) == 0);
    CHECK(out[i].visits.visits.top == golden.visits.top);
    CHECK(out[i].visits.visits.pruned == golden.visits.pruned);
    CHECK(out[i].visits.visits.leaf_points == golden.visits.leaf_points);
    CHECK(out[i].visits.visits.leaf_visits == golden.visits.leaf_visits);
    CHECK(out[i].visits.visits.leader_checks > 0);  // the checks are still made
  }
}

TEST_CASE("a huge thd makes every later query at a leaf follow its first leader", "[hw][approx]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 2000, 23);
  const PointCloud queries = make_queries(cloud, 300, 23);
  std::vector<Case> cases;
  for (const char* r : {"wait", "every_leaf"}) {
    cases.push_back({std::string(r) + " nn", units(8, 4, 8, 4), reading(approximate(mode(Mode::NN), 1e6f), r)});
    cases.push_back(
        {std::string(r) + " radius", units(8, 4, 8, 4), reading(approximate(mode(Mode::Radius, 1, 1.0f), 1e6f), r)});
  }
  const auto out = run_and_check(cloud, queries, cases);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    INFO(cases[i].name);
    const SimOutcome& o = out[i];
    // One leader per non-empty leaf checked at, no more; every other check follows. (wait: a
    // leader counts from its own check, so even queries in flight together follow it.)
    CHECK(leaders(o) <= 16);  // 2^4 leaves
    CHECK(full(o) == 0);
    const std::uint64_t checks = i < 2 ? checked(o) : o.visits.visits.leaf_visits;
    CHECK(followers(o) == checks - leaders(o));
    CHECK(o.visits.visits.leader_checks == followers(o));  // one leader to compare with
  }
}

TEST_CASE("approximate search on the synthetic LiDAR pair: NN, kNN, radius, MQMN", "[hw][approx][synthetic]") {
  const SyntheticPair pair = make_synthetic_pair();
  PointCloud queries;
  for (std::size_t i = 0; i < pair.frame1.size(); i += 29) queries.push_back(pair.frame1[i]);
  auto mqmn = units(16, 8, 16, 10);
  mqmn.be.issue_policy = "mqmn";
  const std::vector<Case> cases = {
      {"nn", units(64, 32, 32, 10), approximate(mode(Mode::NN), 1.2f)},
      {"nn finished_only", units(64, 32, 32, 10), reading(approximate(mode(Mode::NN), 1.2f), "finished_only")},
      {"nn every_leaf", units(64, 32, 32, 10), reading(approximate(mode(Mode::NN), 1.2f), "every_leaf")},
      {"knn10", units(64, 32, 32, 10), approximate(mode(Mode::KNN, 10), 1.2f)},
      {"r0.30", units(64, 32, 32, 10), approximate(mode(Mode::Radius, 1, 0.30f), 0.12f)},
      {"r0.75 mqmn", mqmn, approximate(mode(Mode::Radius, 1, 0.75f), 0.30f)}};
  const auto out = run_and_check(pair.frame0, queries, cases);
  for (std::size_t i = 0; i < out.size(); ++i)
    if (cases[i].name != "nn finished_only") CHECK(followers(out[i]) > 0);
}

TEST_CASE("leader lists that find the Result Buffer's list area full live in DRAM, bit-exact", "[hw][approx]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 3000, 24);
  const PointCloud queries = make_queries(cloud, 300, 24);
  auto tiny = units(8, 4, 8, 5);
  tiny.result_buffer.leader_fraction = 1e-5;  // 31 bytes: less than one 16-byte entry per SU
  auto resident = tiny;                       // the paper's accounting: the same lists stay in the Result Buffer
  resident.result_buffer.leader_lists = hw::LeaderLists::Resident;
  const SearchParams r = approximate(mode(Mode::Radius, 1, 1.0f), 0.4f);
  const std::vector<Case> cases = {{"area", units(8, 4, 8, 5), r}, {"dram", tiny, r}, {"resident", resident, r}};
  const auto out = run_and_check(cloud, queries, cases);
  const auto lists = [](const SimOutcome& o) { return o.buffers["dram"]["leader_list"]; };
  const auto count = [](const SimOutcome& o, const char* key) {
    return o.buffers["leader_buffer"][key].get<std::uint64_t>();
  };
  CHECK(lists(out[0])["write_bytes"].get<std::uint64_t>() == 0);
  CHECK(lists(out[1])["write_bytes"].get<std::uint64_t>() > 0);
  CHECK(lists(out[1])["read_bytes"].get<std::uint64_t>() > 0);
  CHECK(out[0].results.neighbors.size() == out[1].results.neighbors.size());
  // Resident: no list crosses the channel; the overflow is read and written at the Result
  // Buffer's banks instead, every byte the spill moved.
  CHECK(lists(out[2])["write_bytes"].get<std::uint64_t>() == 0);
  CHECK(lists(out[2])["read_bytes"].get<std::uint64_t>() == 0);
  CHECK(count(out[2], "dram_lists") == 0);
  CHECK(count(out[2], "resident_overflow_lists") == count(out[1], "dram_lists"));
  // Radius keeps no slots: every list byte written is a Result Buffer write, or a DRAM one.
  const auto written = [](const SimOutcome& o) { return o.buffers["results"]["write_bytes"].get<std::uint64_t>(); };
  CHECK(written(out[1]) + lists(out[1])["write_bytes"].get<std::uint64_t>() == count(out[1], "list_bytes"));
  CHECK(written(out[2]) == count(out[2], "list_bytes"));
  CHECK(out[2].results.offset == out[1].results.offset);  // both bit-exact against the golden model above
}

TEST_CASE("Leader Check cost (every_leaf): leaders stream past the PEs, then one decision cycle",
          "[hw][approx][timing]") {
  // Brute force (h = 0, one leaf), 1 SU with 1 PE: every batch is one query. Query 0 leads
  // (no check), the other two are within thd and follow it after one check each.
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 200, 25);
  const PointCloud queries = {{0.0f, 0.0f, 0.0f}, {0.01f, 0.0f, 0.0f}, {0.0f, 0.02f, 0.0f}};
  hw::AcceleratorConfig c = units(1, 1, 1, 0);
  c.node_cache.bytes = 0;
  const auto out = run_and_check(cloud, queries, {{"nn", c, reading(approximate(mode(Mode::NN), 1.0f), "every_leaf")}});
  const SimOutcome& o = out[0];
  REQUIRE(leaders(o) == 1);
  REQUIRE(followers(o) == 2);
  const std::uint64_t depth = 3, check = 1, list = 1;      // a NN leader's list: R = k = 1 entry
  const std::uint64_t leader_batch = 200 + 1 - 1 + depth;  // Node Set past 1 PE
  const std::uint64_t follower_batch = (1 + 1 - 1 + depth) + check + (list + 1 - 1 + depth);
  CHECK(o.units["search_units"]["busy_cycles"].get<std::uint64_t>() == leader_batch + 2 * follower_batch);
  // Leader Buffer traffic: one 12-byte leader written, read once by each follower's check.
  const auto& lb = o.buffers["leader_buffer"];
  CHECK(lb["write_bytes"].get<std::uint64_t>() == 12);
  CHECK(lb["read_bytes"].get<std::uint64_t>() == 24);
  CHECK(lb["list_bytes"].get<std::uint64_t>() == 16);
  const hw::EnergyTable e;
  CHECK(o.energy["leader_buffer"].get<double>() == Approx(36 * e.leader_buffer_pj_per_byte));
  CHECK(o.energy["pe"].get<double>() == Approx((200 + 2 * list) * e.distance_pj + 2 * e.leader_check_pj));
}
