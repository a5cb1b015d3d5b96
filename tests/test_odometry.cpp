// The odometry unit (registration/odometry.hpp) on reports made by hand: the chained poses,
// the sums over pairs and stages, pairs.csv and metrics.json's figures, the degenerate pair.
#include <catch2/catch.hpp>

#include <cstdio>
#include <sstream>
#include <string>

#include "registration/odometry.hpp"

using namespace tigris;
using namespace tigris::registration;
using nlohmann::ordered_json;

namespace {

// A pair that moved dx metres forward, with two stages (icp searched in the loop when `accel`).
Report pair_report(double dx, double seconds, bool accel) {
  Report r;
  r.result.transform(0, 3) = dx;
  r.result.total_seconds = seconds;
  StageReport normals;
  normals.name = "normals";
  normals.seconds = seconds / 2;
  normals.search = "exact";
  normals.kdtree.searches = 1000;
  normals.kdtree.search_seconds = seconds / 4;
  StageReport icp = normals;
  icp.name = "icp";
  icp.kdtree.searches = 500;
  if (accel) {
    icp.kdtree.accel.jobs = 9;
    icp.kdtree.accel.modeled_search_seconds = 0.001;
    icp.kdtree.accel.energy_pj = 2e6;
    icp.kdtree.accel.fallback_searches = 3;
    r.accelerator = Report::Accelerator{"auto", ordered_json::object(), ordered_json::array()};
    r.accelerator->job_list.push_back({{"job", 1}, {"sampled", true}});
  }
  r.result.stages = {normals, icp};  // pipeline order: normals before icp
  return r;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

}  // namespace

TEST_CASE("odometry chains the pairs' transforms and sums them", "[odometry]") {
  std::vector<Pose> truth(6, Pose::Identity());  // frames 0..5; the pairs register 2..4
  for (int i = 0; i < 6; ++i) truth[static_cast<std::size_t>(i)](0, 3) = 0.5 * i * i;
  const Odometry odo(2, {pair_report(2.5, 1.0, false), pair_report(3.5, 3.0, false)}, truth, false);
  REQUIRE(odo.estimated().size() == 3);
  CHECK(odo.estimated()[2](0, 3) == 6.0);
  REQUIRE(odo.truth().size() == 3);
  CHECK(odo.truth()[2](0, 3) == 6.0);  // anchored at frame 2: 8 - 2
  CHECK(odo.totals().seconds == 4.0);
  CHECK(odo.totals().kd == 2.0);
  CHECK(odo.totals().not_converged == 0);

  std::ostringstream csv;
  odo.write_pairs_csv(csv);
  const auto rows = lines(csv.str());
  REQUIRE(rows.size() == 3);
  CHECK(rows[0].rfind("pair,source,target,status,seconds,kdtree_seconds", 0) == 0);
  CHECK(rows[1].rfind("0,3,2,converged,1.000000,0.500000,0.5000,1500,", 0) == 0);

  ordered_json m;
  CHECK(odo.add_metrics(m, false).empty());   // steps of 2.5, 3.5, 4.5 m: not equal
  CHECK(m["stages"].begin().key() == "icp");  // by name
  CHECK(m["stages"]["normals"]["per_pair_mean"]["searches"] == 1000.0);
  CHECK(m["kitti"]["too_short"] == true);
  CHECK(m["rpe"]["mean_translation_m"].get<double>() == Approx(0.0).margin(1e-12));  // exact pairs
  CHECK_FALSE(m.contains("accelerator"));

  std::FILE* f = std::tmpfile();
  odo.print_summary(f, m, "seq", "exact", "");
  std::rewind(f);
  char line[256] = {};
  REQUIRE(std::fgets(line, sizeof line, f));
  CHECK(std::string(line) == "tigris odometry: seq, frames 2..4 (2 pairs, 0 not converged), search exact\n");
  REQUIRE(std::fgets(line, sizeof line, f));
  CHECK(std::string(line) == "  registration 4.00 s in all, KD-tree search 2.00 s (50.0%)\n");
  std::fclose(f);
}

TEST_CASE("odometry in the loop sums the accelerator's figures", "[odometry]") {
  const Odometry odo(0, {pair_report(1.0, 1.0, true), pair_report(1.0, 1.0, true)}, {}, true);
  CHECK(odo.totals().jobs == 18);
  CHECK(odo.totals().sampled_jobs == 2);
  CHECK(odo.totals().energy_pj == 4e6);
  ordered_json m;
  CHECK(odo.add_metrics(m, false) == "no poses.txt: no error metrics");
  CHECK(m["ground_truth"].is_null());
  CHECK(m["accelerator"]["per_pair_mean"]["kdtree_energy_pj"] == 2e6);
  CHECK(m["stages"]["icp"]["per_pair_mean"]["accelerator_jobs"] == 9.0);
  CHECK(m["stages"]["normals"]["per_pair_mean"]["accelerator_jobs"] == 0.0);
  std::ostringstream csv;
  odo.write_pairs_csv(csv);
  CHECK(lines(csv.str())[1].find(",3,1") != std::string::npos);  // fallback searches, sampled jobs
}

TEST_CASE("odometry warns of equal ground-truth steps unless the drive is synthetic", "[odometry]") {
  std::vector<Pose> truth(8, Pose::Identity());
  for (int i = 0; i < 8; ++i) truth[static_cast<std::size_t>(i)](0, 3) = 0.86 * i;
  const Odometry odo(0, {pair_report(0.7, 1.0, false)}, truth, false);
  ordered_json m;
  CHECK(odo.add_metrics(m, false).find("equal") != std::string::npos);
  CHECK(m.contains("ground_truth_warning"));
  ordered_json s;
  CHECK(odo.add_metrics(s, true).empty());
  CHECK_FALSE(s.contains("ground_truth_warning"));
}

TEST_CASE("odometry refuses to chain past a degenerate pair, naming it", "[odometry]") {
  Report bad = pair_report(1.0, 1.0, false);
  bad.result.status = "degenerate";
  bad.result.problem = "a flat scene";
  try {
    Odometry(4, {pair_report(1.0, 1.0, false), bad}, {}, false);
    FAIL("no error");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("pair 000006 -> 000005 is degenerate (no transform: a flat scene)") !=
          std::string::npos);
  }
}
