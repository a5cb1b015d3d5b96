// Sampled simulation's plan and estimator (testbench/sampling.hpp). Whole sampled runs against
// full ones: tests/sampling_test.py.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <set>

#include "hw_cases.hpp"
#include "sw_ref/search.hpp"
#include "testbench/accel_job.hpp"
#include "testbench/config.hpp"
#include "testbench/sampling.hpp"
#include "testbench/scoreboard.hpp"
#include "workloads/synthetic.hpp"

using namespace tigris;

namespace {

hw::AcceleratorConfig::Sim sim(double sampling, int windows = 20) {
  hw::AcceleratorConfig::Sim s;
  s.sampling = sampling;
  s.windows = windows;
  return s;
}

constexpr double kAuto = hw::AcceleratorConfig::Sim::kAuto;

}  // namespace

TEST_CASE("scoreboard: exact search's schedule, checked against the golden order, fails where the replay fails",
          "[sampling]") {
  const SyntheticPair pair = make_synthetic_pair();
  PointCloud cloud, queries;
  for (std::size_t i = 0; i < pair.frame0.size(); i += 8) cloud.push_back(pair.frame0[i]);
  for (std::size_t i = 0; i < pair.frame1.size(); i += 40) queries.push_back(pair.frame1[i]);
  const KdTree tree = build_kdtree(cloud, 6);
  for (const SearchParams& params : {test::mode(Mode::NN), test::mode(Mode::KNN, 8)}) {
    const SearchOutput golden = golden_search(tree, queries, params);
    // The accelerator's schedule: the golden rows interleaved (last query first), then spoilt.
    Schedule interleaved = golden.schedule;
    std::stable_sort(interleaved.begin(), interleaved.end(),
                     [](const ScheduleEntry& a, const ScheduleEntry& b) { return a.query > b.query; });
    SearchOutput hw = golden;
    hw.schedule = interleaved;
    CHECK(check_against_golden(tree, queries, params, golden, golden.results, hw).match);
    std::size_t two = 0;  // a row whose query visits another leaf after it
    while (two + 1 < interleaved.size() && interleaved[two].query != interleaved[two + 1].query) ++two;
    REQUIRE(two + 1 < interleaved.size());
    std::vector<Schedule> spoilt(6, interleaved);
    spoilt[0][3].leaf ^= 1;                                           // a visit the traversal does not make
    std::swap(spoilt[1][two], spoilt[1][two + 1]);                    // one query's leaves out of order
    spoilt[2].erase(spoilt[2].begin() + 5);                           // a visit missing
    spoilt[3].push_back(spoilt[3].back());                            // a visit after the query finished
    spoilt[4][7].query = static_cast<std::uint32_t>(queries.size());  // no such query
    spoilt[5][2].event = ScheduleEntry::Event::Finish;                // a leader's finish row
    for (std::size_t i = 0; i < spoilt.size(); ++i) {
      INFO("spoilt schedule " << i);
      hw.schedule = spoilt[i];
      std::string replay_says;
      try {
        search(tree, queries, params, &spoilt[i]);
      } catch (const ScheduleError& e) {
        replay_says = e.what();
      }
      REQUIRE_FALSE(replay_says.empty());
      const Verdict v = check_against_golden(tree, queries, params, golden, golden.results, hw);
      CHECK_FALSE(v.match);
      REQUIRE(v.first.size() == 1);
      CHECK(v.first[0] == "the accelerator's schedule does not replay: " + replay_says);
    }
  }
}

TEST_CASE("sampling: off, approximate search and short jobs are simulated in full, saying why", "[sampling]") {
  const SamplingPlan off = plan_sampling(sim(0), 100000, 300, false);
  CHECK_FALSE(off.sampled);
  CHECK(off.why == "sim.sampling is off");
  CHECK(off.stream.empty());
  const SamplingPlan approx = plan_sampling(sim(kAuto), 100000, 300, true);
  CHECK_FALSE(approx.sampled);
  CHECK(approx.why.find("approximate search") != std::string::npos);
  // The paper's machine: 124,605 KITTI queries, 15,728 in flight.
  const SamplingPlan kitti = plan_sampling(sim(kAuto), 124605, 15728, false);
  CHECK_FALSE(kitti.sampled);
  CHECK(kitti.why.find("too short to sample") != std::string::npos);
  CHECK(kitti.why.find("15728 in flight") != std::string::npos);
  // Long enough to fit, too short to gain: auto simulates in full what would take over a third.
  const SamplingPlan marginal = plan_sampling(sim(kAuto), 60000, 1000, false);
  CHECK_FALSE(marginal.sampled);
  CHECK(marginal.why.find("too short to gain") != std::string::npos);
  // A share too small for the windows.
  const SamplingPlan tiny = plan_sampling(sim(0.01), 100000, 300, false);
  CHECK_FALSE(tiny.sampled);
  CHECK(tiny.why.find("fewer than") != std::string::npos);
}

TEST_CASE("sampling: auto's stream is the fill, evenly spread windows after warming and the drain", "[sampling]") {
  const std::uint32_t n = 115110, in_flight = 315;
  const SamplingPlan p = plan_sampling(sim(kAuto), n, in_flight, false);
  REQUIRE(p.sampled);
  CHECK(p.warm == in_flight);
  CHECK(p.measured == in_flight);
  CHECK(p.fill == 2 * in_flight);
  CHECK(p.drain == 2 * in_flight);
  REQUIRE(p.windows.size() == 20);
  CHECK(p.stream.size() == p.fill + 20 * p.measured + 19 * p.warm + p.drain);
  // Ascending job ids, no repeats; the fill is the job's first queries, the drain its last.
  CHECK(std::set<std::uint32_t>(p.stream.begin(), p.stream.end()).size() == p.stream.size());
  for (std::size_t i = 1; i < p.stream.size(); ++i) REQUIRE(p.stream[i] > p.stream[i - 1]);
  for (std::uint32_t q = 0; q < p.fill; ++q) REQUIRE(p.stream[q] == q);
  CHECK(p.stream.back() == n - 1);
  CHECK(p.stream[p.stream.size() - p.drain] == n - p.drain);
  // Each window: consecutive queries, the first right after the fill; each later one after
  // `warm` consecutive queries of its own; the window starts spread evenly over the job.
  CHECK(p.windows.front().from == p.fill);
  std::uint32_t previous_start = 0;
  for (std::size_t j = 0; j < p.windows.size(); ++j) {
    const auto& w = p.windows[j];
    REQUIRE(w.to - w.from == p.measured);
    for (std::uint32_t i = w.from + 1; i < w.to; ++i) REQUIRE(p.stream[i] == p.stream[i - 1] + 1);
    if (j > 0) {
      for (std::uint32_t i = w.from - p.warm + 1; i <= w.from; ++i) REQUIRE(p.stream[i] == p.stream[i - 1] + 1);
      const std::uint32_t spacing = p.stream[w.from] - previous_start;
      CHECK(spacing >= (n - p.fill - p.drain) / 20);
      CHECK(spacing <= (n - p.fill - p.drain) / 20 + 1);
    }
    previous_start = p.stream[w.from];
  }
  CHECK(p.windows.back().to == p.stream.size() - p.drain);
}

TEST_CASE("sampling: a share simulates that share of the queries", "[sampling]") {
  for (double share : {0.1, 0.25, 0.5}) {
    const SamplingPlan p = plan_sampling(sim(share), 100000, 300, false);
    REQUIRE(p.sampled);
    CHECK(std::abs(static_cast<double>(p.stream.size()) - share * 100000) <= 21);
  }
}

TEST_CASE("sampling: the ratio estimate and its interval", "[sampling]") {
  // Proportional segments: the ratio exactly, no spread.
  const RatioEstimate exact = ratio_estimate({20, 40, 60}, {10, 20, 30});
  CHECK(exact.ratio == Approx(2.0));
  CHECK(exact.half == Approx(0.0).margin(1e-12));
  // A linear trend along the job is no sampling error for successive differences: residuals
  // 1, 0, -1 differ by 1 each, a variance of 1/2 per segment.
  const RatioEstimate trend = ratio_estimate({11, 10, 9}, {10, 10, 10});
  CHECK(trend.ratio == Approx(1.0));
  CHECK(trend.half == Approx(student_t95(2) * std::sqrt(0.5 / 3) / 10));
  // Alternating residuals count in full: 1, -1, 1 differ by 2 each, a variance of 2.
  const RatioEstimate noisy = ratio_estimate({11, 9, 11}, {10, 10, 10});
  CHECK(noisy.half == Approx(student_t95(2) * std::sqrt(2.0 / 3) / 10));
  CHECK(student_t95(1) == Approx(12.706));
  CHECK(student_t95(19) == Approx(2.093));
  CHECK(student_t95(1000) == Approx(1.96).epsilon(0.002));
}

TEST_CASE("sampling: sim.sampling takes off, auto or a share; others are errors naming the key", "[sampling]") {
  hw::AcceleratorConfig cfg;
  CHECK(cfg.sim.sampling == 0);
  apply_setting(cfg, "sim.sampling=auto");
  CHECK(cfg.sim.sampling == kAuto);
  CHECK(config_to_json(cfg)["sim"]["sampling"] == "auto");
  apply_setting(cfg, "sim.sampling=0.25");
  CHECK(cfg.sim.sampling == 0.25);
  apply_config_json(cfg, {{"sim", {{"sampling", "off"}}}}, "f.json");
  CHECK(cfg.sim.sampling == 0);
  CHECK(config_to_json(cfg)["sim"]["sampling"] == "off");
  CHECK_THROWS_WITH(apply_setting(cfg, "sim.sampling=1.5"),
                    Catch::Contains("sim.sampling") && Catch::Contains("out of range"));
  CHECK_THROWS_WITH(apply_setting(cfg, "sim.sampling=some"),
                    Catch::Contains("sim.sampling") && Catch::Contains("off") && Catch::Contains("auto"));
  CHECK_THROWS_WITH(apply_config_json(cfg, {{"sim", {{"sampling", -0.5}}}}, "f.json"),
                    Catch::Contains("f.json") && Catch::Contains("out of range"));
  CHECK_NOTHROW(validate_config(cfg));
}

TEST_CASE("scoreboard: the golden search on two threads gives what one search gives", "[sampling]") {
  const SyntheticPair pair = make_synthetic_pair();
  PointCloud cloud, queries;
  for (std::size_t i = 0; i < pair.frame0.size(); i += 4) cloud.push_back(pair.frame0[i]);
  for (std::size_t i = 0; i < pair.frame1.size(); i += 9) queries.push_back(pair.frame1[i]);
  const KdTree tree = build_kdtree(cloud, 8);
  for (const SearchParams& params :
       {test::mode(Mode::NN), test::mode(Mode::KNN, 8), test::mode(Mode::Radius, 1, 0.6f)}) {
    const SearchOutput one = search(tree, queries, params);
    const SearchOutput two = golden_search(tree, queries, params);
    CHECK_FALSE(first_difference(one.results, two.results));
    REQUIRE(one.per_query.size() == two.per_query.size());
    for (std::size_t q = 0; q < one.per_query.size(); ++q) {
      REQUIRE(one.per_query[q].leaf_points == two.per_query[q].leaf_points);
      REQUIRE(one.per_query[q].top == two.per_query[q].top);
    }
    CHECK(one.visits.leaf_points == two.visits.leaf_points);
    CHECK(one.visits.leaf_visits == two.visits.leaf_visits);
    CHECK(one.schedule == two.schedule);
    // Replaying a schedule (here the search's own, last query first) checks every row either way.
    Schedule reversed = one.schedule;
    std::stable_sort(reversed.begin(), reversed.end(),
                     [](const ScheduleEntry& a, const ScheduleEntry& b) { return a.query > b.query; });
    const SearchOutput replayed = golden_search(tree, queries, params, &reversed);
    CHECK_FALSE(first_difference(one.results, replayed.results));
    Schedule bad = one.schedule;
    bad.back().leaf ^= 1;  // a visit the query's traversal does not make
    CHECK_THROWS_AS(golden_search(tree, queries, params, &bad), ScheduleError);
  }
}

TEST_CASE("model job: a tree built ahead is taken when it is the job's, else the job builds its own", "[sampling]") {
  const SyntheticPair pair = make_synthetic_pair();
  PointCloud cloud, queries;
  for (std::size_t i = 0; i < pair.frame0.size(); i += 8) cloud.push_back(pair.frame0[i]);
  for (std::size_t i = 0; i < pair.frame1.size(); i += 80) queries.push_back(pair.frame1[i]);
  const SearchParams params = test::mode(Mode::KNN, 8);
  hw::AcceleratorConfig cfg;
  cfg.tree.top_height = 6;
  const PreparedJob own = prepare_job(cloud, queries, params, cfg, WorkLimits{}, "");
  // The loop's server builds it once (accel_in_loop.cpp); a job moves it out, not a copy.
  BuiltTree built = BuiltTree::of(cloud, 6, cfg.tree.split_axis);
  const PreparedJob taken = prepare_job(cloud, queries, params, cfg, WorkLimits{}, "", &built);
  CHECK(built.tree.top.empty());
  CHECK(taken.tree.leaf_index == own.tree.leaf_index);
  CHECK(taken.image.bytes == own.image.bytes);
  // Another height's tree, or another cloud's, is not the job's: it builds its own.
  for (const PointCloud& points : {cloud, queries}) {
    built = BuiltTree::of(points, points.size() == cloud.size() ? 5 : 6, cfg.tree.split_axis);
    const PreparedJob rebuilt = prepare_job(cloud, queries, params, cfg, WorkLimits{}, "", &built);
    CHECK_FALSE(built.tree.top.empty());
    CHECK(rebuilt.image.bytes == own.image.bytes);
  }
}
