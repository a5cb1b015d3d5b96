// What a run says about itself: the bottleneck classification on crafted statistics, the derived
// fields' formulas, and the inputs' SHA-256 against the published test vector.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/out_folder.hpp"
#include "testbench/bottleneck.hpp"
#include "testbench/run_inputs.hpp"
#include "testbench/stat_formulas.hpp"

using nlohmann::json;

namespace {

// A stats JSON of `cycles` cycles with 4 RUs and 2 SUs whose busy and stall cycles are the given
// fractions of each kind's unit-cycles.
json stats(double cycles, double ru_busy, json ru_stalls, double su_busy, json su_stalls) {
  for (auto& [k, v] : ru_stalls.items()) v = v.get<double>() * 4 * cycles;
  for (auto& [k, v] : su_stalls.items()) v = v.get<double>() * 2 * cycles;
  return {{"cycles", cycles},
          {"lower_bound_cycles", cycles / 4},
          {"units",
           {{"recursion_units", {{"count", 4}, {"busy_cycles", ru_busy * 4 * cycles}, {"stall_cycles", ru_stalls}}},
            {"search_units",
             {{"count", 2},
              {"busy_cycles", su_busy * 2 * cycles},
              {"stall_cycles", su_stalls},
              {"pe_utilization", 0.25}}}}}};
}

}  // namespace

TEST_CASE("bottleneck: RUs occupied more than SUs is front-end bound, named by the largest part", "[report]") {
  const json b = tigris::bottleneck_json(
      stats(1000, 0.45, {{"sram", 0.49}, {"bqb_full", 0.01}, {"injected", 0.0}}, 0.74, {{"issue_search", 0.01}}));
  CHECK(b["bound"] == "front-end");
  CHECK(b["unit"] == "recursion_units");
  CHECK(b["occupancy"].get<double>() == Approx(0.94));  // BQB-full waits on the back-end
  CHECK(b["cause"] == "sram stall");
  CHECK(b["share"].get<double>() == Approx(0.49));
  CHECK(b["runner_up"]["unit"] == "search_units");
  CHECK(b["runner_up"]["occupancy"].get<double>() == Approx(0.75));
  CHECK(b["runner_up"]["cause"] == "busy");
  CHECK(b["cycles_over_lower_bound"].get<double>() == Approx(4.0));
  const std::string s = b["summary"];
  CHECK(s.rfind("front-end (RU) bound: RUs 94% occupied: sram stall 49%, busy 45%; waiting on other blocks 1%: "
                "bqb_full stall 1%",
                0) == 0);
  CHECK(s.find("SUs 75% occupied: busy 74%, issue_search stall 1%") != std::string::npos);
  CHECK(s.find("PE utilization 25%") != std::string::npos);
  CHECK(s.find("cycles 4.0x the lower bound") != std::string::npos);
  CHECK(s.find("injected") == std::string::npos);  // a zero stall is not listed
}

TEST_CASE("bottleneck: SUs occupied more is back-end bound, busy as the cause", "[report]") {
  const json b = tigris::bottleneck_json(stats(500, 0.30, {{"sram", 0.10}}, 0.90, {{"issue_search", 0.05}}));
  CHECK(b["bound"] == "back-end");
  CHECK(b["unit"] == "search_units");
  CHECK(b["cause"] == "busy");
  CHECK(b["share"].get<double>() == Approx(0.90));
  CHECK(b["runner_up"]["unit"] == "recursion_units");
  CHECK(b["runner_up"]["cause"] == "busy");
  CHECK(b["summary"].get<std::string>().rfind("back-end (SU) bound", 0) == 0);
}

TEST_CASE("bottleneck: RUs held by full BE Query Buffers are back-pressure, so the back-end bounds", "[report]") {
  // 16 SUs: the RUs are 92% busy or stalled, but 32% of it is waiting for BQB room.
  const json b = tigris::bottleneck_json(stats(1000, 0.40, {{"sram", 0.20}, {"bqb_full", 0.32}}, 0.90, json::object()));
  CHECK(b["bound"] == "back-end");
  CHECK(b["unit"] == "search_units");
  CHECK(b["runner_up"]["occupancy"].get<double>() == Approx(0.60));
  CHECK(b["summary"].get<std::string>().find("waiting on other blocks 32%: bqb_full stall 32%") != std::string::npos);
}

TEST_CASE("bottleneck: a write-back wait above 30% bounds the run whatever is busiest", "[report]") {
  // SUs wait 31% on the write-back; the RUs are the more occupied kind.
  const json b = tigris::bottleneck_json(stats(800, 0.60, {{"sram", 0.35}}, 0.10, {{"result_writeback", 0.31}}));
  CHECK(b["bound"] == "result write-back");
  CHECK(b["unit"] == "search_units");
  CHECK(b["cause"] == "result_writeback stall");
  CHECK(b["share"].get<double>() == Approx(0.31));
  CHECK(b["runner_up"]["unit"] == "recursion_units");
  CHECK(b["runner_up"]["cause"] == "busy");
  // At exactly 30% the ordinary rule applies.
  const json edge = tigris::bottleneck_json(stats(800, 0.60, {{"sram", 0.35}}, 0.10, {{"result_writeback", 0.30}}));
  CHECK(edge["bound"] == "front-end");
}

TEST_CASE("bottleneck: a run of no cycles has none", "[report]") {
  const json b = tigris::bottleneck_json(stats(0, 0, json::object(), 0, json::object()));
  CHECK(b["bound"] == "none");
}

TEST_CASE("inputs: SHA-256 of a file is the digest sha256sum prints", "[report]") {
  const std::string path = "test_run_report_abc.txt";
  { std::ofstream(path, std::ios::binary) << "abc"; }
  CHECK(tigris::sha256_of_file(path) == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  const json in = tigris::input_file("cloud", path);
  CHECK(in["bytes"] == 3);
  CHECK(in["path"] == path);
  std::remove(path.c_str());
  CHECK_THROWS_WITH(tigris::sha256_of_file(path), Catch::Contains(path));
}

TEST_CASE("output core: an input that changes during the run is named before any result is written", "[report]") {
  namespace fs = std::filesystem;
  const std::string dir = "test_run_report_folder", path = "test_run_report_source.bin";
  fs::remove_all(dir);
  { std::ofstream(path, std::ios::binary) << "frame 1"; }
  {
    tigris::FolderSpec spec{
        "register", {}, json::object(), json::array({tigris::input_file("source", path)}), {"registration.json"},
        false,      {}};
    tigris::OutFolder folder(dir, spec);
    CHECK_NOTHROW(folder.check_inputs());
    { std::ofstream(path, std::ios::binary) << "frame 2"; }  // issue 54, 8: --source replaced mid-run
    CHECK_THROWS_WITH(folder.check_inputs(), Catch::Contains("the input source (" + path + ") changed while"));
  }
  fs::remove_all(dir);
  std::remove(path.c_str());
}

TEST_CASE("bottleneck: PI/RS dependency stalls are busy cycles, not added again", "[report]") {
  // Without forwarding: 30% of the RUs' cycles are PI/RS stalls inside their 80% busy.
  const json b =
      tigris::bottleneck_json(stats(1000, 0.80, {{"pi_rs_dependency", 0.30}, {"sram", 0.10}}, 0.50, json::object()));
  CHECK(b["occupancy"].get<double>() == Approx(0.90));
  CHECK(b["summary"].get<std::string>().find("pi_rs") == std::string::npos);
}

TEST_CASE("stat formulas: arithmetic left to right, max, missing fields and division by zero", "[stats]") {
  const json s = {{"cycles", 1000}, {"units", {{"a", {{"busy", 250}, {"count", 2}}}}}, {"zero", 0}, {"text", "x"}};
  CHECK(*tigris::evaluate("units.a.busy / (units.a.count * cycles)", s) == 0.125);
  CHECK(*tigris::evaluate("1 + 2 * 3 - 4 / 2", s) == 5.0);
  CHECK(*tigris::evaluate("max(cycles / 8, units.a.busy)", s) == 250.0);
  CHECK(*tigris::evaluate("cycles * 1e-3", s) == 1.0);
  CHECK(*tigris::evaluate("cycles / zero", s) == 0.0);  // an idle unit has no utilization
  CHECK_FALSE(tigris::evaluate("units.b.busy / cycles", s).has_value());
  CHECK_FALSE(tigris::evaluate("max(cycles, nothing)", s).has_value());
  CHECK_THROWS_WITH(tigris::evaluate("cycles / (units.a.count", s), Catch::Contains("expected ')'"));
  CHECK_THROWS_WITH(tigris::evaluate("cycles +", s), Catch::Contains("ends early"));
  CHECK_THROWS_WITH(tigris::evaluate("text * 2", s), Catch::Contains("field text is not a number"));
  CHECK_THROWS_WITH(tigris::evaluate("cycles cycles", s), Catch::Contains("unexpected 'c'"));
}

TEST_CASE("stat formulas: every derived field names fields that a run writes", "[stats]") {
  // Each formula parses, and over a stats JSON holding every field it names it gives a value.
  json s = {{"cycles", 1000},
            {"config",
             {{"clock_mhz", 500}, {"fe", {{"recursion_units", 4}}}, {"be", {{"search_units", 2}, {"pes_per_su", 8}}}}},
            {"visits", {{"top", 100}, {"leaf_points", 800}, {"follower_points", 160}, {"leader_checks", 40}}},
            {"energy_pj", {{"total", 5e6}}},
            {"units",
             {{"recursion_units", {{"busy_cycles", 2000}, {"count", 4}}},
              {"search_units",
               {{"busy_cycles", 500},
                {"pe_busy_cycles", 4000},
                {"count", 2},
                {"pes_per_su", 8},
                {"queries", 30},
                {"batches", 10}}}}}};
  tigris::add_derived(s);
  CHECK(s["seconds"].get<double>() == 1000 / 500e6);
  CHECK(s["units"]["recursion_units"]["utilization"].get<double>() == 0.5);
  CHECK(s["units"]["search_units"]["utilization"].get<double>() == 0.25);
  CHECK(s["units"]["search_units"]["pe_utilization"].get<double>() == 0.25);
  CHECK(s["units"]["search_units"]["queries_per_batch"].get<double>() == 3.0);
  CHECK(s["power_w"].get<double>() == Approx(5e6 * 1e-12 / (1000 / 500e6)));
  // The ideal machine: every distance a PE computes (leaf, follower and leader-check) over the
  // 16 PEs, against 100 top nodes over 4 RUs.
  CHECK(s["visits"]["pe_distances"].get<double>() == 1000.0);
  CHECK(s["lower_bound_cycles"].get<double>() == 62.5);
  for (const tigris::DerivedStat& d : tigris::derived_stats()) CHECK(tigris::evaluate(d.formula, s).has_value());
}
