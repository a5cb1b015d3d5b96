// CPU baselines with repeats and spread: a fake slow back-end (a function
// that sleeps a known time per run) is timed as register --compare times its CPU rows, and the
// median, range, speed-up range and warnings are checked against the sleeps.
#include <catch2/catch.hpp>

#include <chrono>
#include <thread>

#include "testbench/cpu_baseline.hpp"

using namespace tigris;

namespace {
// Wall seconds of one call of a back-end that sleeps `ms` milliseconds.
double fake_backend_seconds(int ms) {
  const auto t0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(ms));
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

TEST_CASE("cpu baseline: a fake slow back-end's median and range come from its runs", "[baseline]") {
  std::vector<double> slow;
  for (int ms : {90, 30, 60}) slow.push_back(fake_backend_seconds(ms));
  const Spread s = spread_of(slow);
  CHECK(s.samples == slow);  // in the order measured
  CHECK(s.median == slow[2]);
  CHECK(s.min == slow[1]);
  CHECK(s.max == slow[0]);
  CHECK(s.min >= 0.030);
  CHECK(s.median >= 0.060);
  CHECK(s.median < s.max);

  // Against a modeled row of 3 ms: the median ratio and the widest range the runs allow.
  const nlohmann::ordered_json r = ratio_range(s, exact_value(0.003));
  CHECK(r["median"].get<double>() == Approx(s.median / 0.003));
  CHECK(r["min"].get<double>() == Approx(s.min / 0.003));
  CHECK(r["max"].get<double>() == Approx(s.max / 0.003));
  // Two measured rows: base min over row max .. base max over row min.
  const Spread fast = spread_of({0.010, 0.020});
  CHECK(fast.median == Approx(0.015));
  const nlohmann::ordered_json q = ratio_range(s, fast);
  CHECK(q["min"].get<double>() == Approx(s.min / 0.020));
  CHECK(q["max"].get<double>() == Approx(s.max / 0.010));
  const nlohmann::ordered_json red = reduction_range_percent(s, fast);
  CHECK(red["min"].get<double>() == Approx(100.0 * (1.0 - 0.020 / s.min)));
  CHECK(red["max"].get<double>() == Approx(100.0 * (1.0 - 0.010 / s.max)));

  const nlohmann::ordered_json j = to_json(s);
  CHECK(j["samples"].size() == 3);
  CHECK(spread_cell(spread_of({2.0, 1.0, 3.0}), "%.1f") == "2.0 [1.0-3.0]");
  CHECK(spread_cell(exact_value(2.0), "%.1f") == "2.0");
}

TEST_CASE("cpu baseline: refusals and warnings", "[baseline]") {
  CHECK_THROWS_AS(spread_of({}), std::invalid_argument);
  CHECK_THROWS_AS(spread_of({1.0, NAN}), std::invalid_argument);
  CHECK(ratio_range(exact_value(1.0), exact_value(0.0))["median"].is_null());

  Machine m;
  m.cores = 2;
  m.load_before = {0.1, 0.1, 0.1};
  CHECK(baseline_warnings(m, {{"flann", spread_of({1.0, 1.1, 1.05})}}).empty());
  const auto once = baseline_warnings(m, {{"flann", exact_value(1.0)}});
  REQUIRE(once.size() == 1);
  CHECK(once[0].find("timed once") != std::string::npos);
  const auto wide = baseline_warnings(m, {{"flann", spread_of({1.0, 1.6, 1.1})}});
  REQUIRE(wide.size() == 1);
  CHECK(wide[0].find("varied by 55%") != std::string::npos);
  m.load_before = {1.5, 1.0, 1.0};
  const auto busy = baseline_warnings(m, {{"flann", spread_of({1.0, 1.1, 1.05})}});
  REQUIRE(busy.size() == 1);
  CHECK(busy[0].find("busy") != std::string::npos);
}

TEST_CASE("cpu baseline: the machine names its CPU, cores, loads and commit", "[baseline]") {
  Machine m = machine_before();
  machine_after(m);
  CHECK(m.cores >= 1);
  CHECK(!m.cpu_model.empty());
  CHECK(!m.commit.empty());
  const nlohmann::ordered_json j = to_json(m);
  for (const char* k : {"cpu_model", "cores", "host", "commit", "load_average_before", "load_average_after"})
    CHECK(j.contains(k));
  CHECK(j["load_average_before"].contains("1min"));
  CHECK(machine_line(m).find("commit " + m.commit) != std::string::npos);
}
