// registration.json's one reader and writer (registration/report.hpp): a report read back and
// written again is the same text; every field the readers use comes back typed; a report that
// is not whole is refused naming the file and the key.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "registration/report.hpp"

using namespace tigris;
using namespace tigris::registration;
using nlohmann::ordered_json;

namespace {

StageReport stage(const std::string& name, const std::string& search, double seconds, std::uint64_t searches) {
  StageReport s;
  s.name = name;
  s.seconds = seconds;
  s.search = search;
  s.kdtree.searches = searches;
  s.kdtree.neighbors = 3 * searches;
  s.kdtree.builds = 2;
  s.kdtree.search_seconds = seconds / 3;
  s.kdtree.build_seconds = seconds / 7;
  s.kdtree.visits.top = 11 * searches;
  s.kdtree.visits.leaf_visits = searches + 1;
  return s;
}

// A report in the loop with every part a registration can have: stages with and without
// searches, stage counts, ground truth with a warning, an injection, a job list, a trace.
Report full_report() {
  Report r;
  r.source = {"b.bin", 120000};
  r.target = {"a.bin", 119000};
  r.preset = "dp4";
  r.search = "accel";
  r.injection = {3, 0.2, 0.9, 0.45};
  r.result.transform << 0.999, -0.01, 0.002, 0.71, 0.01, 0.999, 0.0, -0.02, 0.0, 0.0, 1.0, 0.003, 0, 0, 0, 1;
  r.result.initial(0, 3) = 0.69;
  r.result.total_seconds = 2.25;
  r.result.status = "not_converged";
  r.result.problem = "ICP ran out of correspondences";
  StageReport outliers = stage("outlier_removal", "exact", 0.75, 120000);
  outliers.kdtree.accel.jobs = 2;
  outliers.kdtree.accel.queries = 239000;
  outliers.kdtree.accel.cycles = 123456789;
  outliers.kdtree.accel.modeled_search_seconds = 0.0123;
  outliers.kdtree.accel.modeled_host_seconds = 0.0004;
  outliers.kdtree.accel.fallback_searches = 5;
  outliers.kdtree.accel.fallback_seconds = 1e-5;
  outliers.kdtree.accel.energy_pj = 4.5e6;
  outliers.kdtree.accel.visits.pruned = 77;
  outliers.info = {{"removed_source", 12}, {"kept", {1, 2}}};
  StageReport keypoints;
  keypoints.name = "keypoints";
  keypoints.seconds = 0.125;
  keypoints.info = {{"source_keypoints", 900}};
  StageReport icp = stage("icp", "exact", 1.375, 4000);
  icp.kdtree.accel.jobs = 9;
  r.result.stages = {outliers, keypoints, icp};
  r.work_spent = 4.25e8;
  r.max_work = 1e10;
  r.accelerator = Report::Accelerator{"auto", {{"be", {{"search_units", 32}}}}, ordered_json::array()};
  r.accelerator->job_list.push_back({{"job", 1}, {"sampled", true}});
  r.accelerator->job_list.push_back({{"job", 2}, {"sampled", false}});
  Pose truth = Pose::Identity();
  truth(0, 3) = 0.86;
  r.truth = Report::Truth{"poses.txt frames 1,0", truth, "equal steps"};
  r.config = {{"icp", {{"max_iterations", 30}}}};
  r.trace = {{"path", "t.bin"}, {"jobs", 71}, {"clouds", 4}};
  return r;
}

std::string text_of(const Report& r) { return to_json(r).dump(2); }

// The message of the error reading `doc` gives, or "" when it reads.
std::string refusal(const ordered_json& doc) {
  try {
    report_from_json(doc, "O/registration.json");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a registration report reads back into the same text and the same figures", "[report]") {
  const Report r = full_report();
  const ordered_json doc = to_json(r);
  const Report back = report_from_json(ordered_json::parse(doc.dump()), "mem");
  CHECK(text_of(back) == doc.dump(2));
  CHECK(doc["version"] == Report::kVersion);
  // The typed fields the readers use (odometry's pairs, --compare's rows).
  CHECK(back.result.status == "not_converged");
  CHECK(back.result.problem == r.result.problem);
  CHECK(back.result.transform == r.result.transform);
  CHECK(back.result.total_seconds == r.result.total_seconds);
  REQUIRE(back.result.stages.size() == 3);
  CHECK(back.result.stages[1].name == "keypoints");  // the file's order, not by name
  CHECK(back.result.stages[1].search.empty());
  CHECK(back.result.stages[0].kdtree.accel.cycles == 123456789);
  CHECK(back.result.stages[0].kdtree.visits.top == 11 * 120000);
  CHECK(back.result.stages[0].info["kept"] == nlohmann::json({1, 2}));
  CHECK(back.in_loop());
  CHECK(back.sampled_jobs() == 1);
  const LoopFigures a = loop_figures(r.result), b = loop_figures(back.result);
  CHECK(b.modeled_e2e == a.modeled_e2e);
  CHECK(b.modeled_kd == a.modeled_kd);
  CHECK(b.jobs == 11);
  CHECK(b.fallback_searches == 5);
  CHECK(doc["accelerator"]["modeled_end_to_end_seconds"].get<double>() == a.modeled_e2e);
  CHECK(doc["stages"]["outlier_removal"]["accelerator"]["modeled_stage_seconds"].get<double>() ==
        modeled_stage_seconds(r.result.stages[0]));
  REQUIRE(back.error());
  CHECK(back.error()->translation_m == r.error()->translation_m);
  CHECK(doc["error"]["translation_m"].get<double>() == r.error()->translation_m);
  CHECK(doc["ground_truth"]["warning"] == "equal steps");
  CHECK(doc["injection"]["normals_shell"] == ordered_json::array({0.2, 0.9}));
  CHECK(back.trace == r.trace);
}

TEST_CASE("a report on the CPU and a degenerate one read back alike", "[report]") {
  Report r = full_report();
  r.accelerator.reset();
  r.search = "approx";
  r.result.stages[0].kdtree.leaders = {5, 6, 7};
  r.result.stages[0].search = "approx";
  r.trace = nullptr;
  r.injection = {1, 0, 0, 0.45};
  ordered_json doc = to_json(r);
  CHECK_FALSE(doc.contains("accelerator"));
  CHECK(doc["stages"]["outlier_removal"]["leaders"]["leader_buffer_full"] == 7);
  CHECK(doc["injection"]["normals_shell"].is_null());
  CHECK(text_of(report_from_json(ordered_json::parse(doc.dump()), "mem")) == doc.dump(2));

  r.result.status = "degenerate";
  r.result.transform = Pose::Constant(std::numeric_limits<double>::quiet_NaN());
  doc = to_json(r);
  CHECK(doc["transform"].is_null());
  CHECK_FALSE(doc.contains("error"));  // no error without a transform
  CHECK_FALSE(doc.contains("ground_truth"));
  const Report back = report_from_json(ordered_json::parse(doc.dump()), "mem");
  CHECK(back.degenerate());
  CHECK(std::isnan(back.result.transform(0, 0)));
  CHECK(text_of(back) == doc.dump(2));
}

TEST_CASE("a report written before the version field reads as version 1", "[report]") {
  ordered_json doc = to_json(full_report());
  doc.erase("version");
  CHECK(report_from_json(doc, "old").result.stages.size() == 3);
}

TEST_CASE("a report that is not whole is refused naming the file and the key", "[report]") {
  const ordered_json good = to_json(full_report());
  CHECK(refusal(good).empty());
  const auto spoilt = [&](auto&& edit) {
    ordered_json d = good;
    edit(d);
    return refusal(d);
  };
  const auto has = [](const std::string& message, const std::string& part) {
    INFO(message);
    CHECK(message.rfind("O/registration.json: ", 0) == 0);
    CHECK(message.find(part) != std::string::npos);
    CHECK(message.find("not a whole tigris register report") != std::string::npos);
  };
  has(refusal(ordered_json::array()), "not a JSON object");
  has(spoilt([](ordered_json& d) { d.erase("stages"); }), "no 'stages'");
  has(spoilt([](ordered_json& d) { d["stages"] = ordered_json::object(); }), "no 'stages'");
  has(spoilt([](ordered_json& d) { d.erase("status"); }), "no 'status' text");
  has(spoilt([](ordered_json& d) { d["seconds"] = -1; }), "'seconds'");
  has(spoilt([](ordered_json& d) { d["stages"]["icp"]["seconds"] = "fast"; }), "stage 'icp': 'seconds'");
  has(spoilt([](ordered_json& d) { d["stages"]["icp"]["searches"] = 2.5; }), "stage 'icp': 'searches' is not a count");
  has(spoilt([](ordered_json& d) { d["stages"]["icp"] = 3; }), "stage 'icp' is not an object");
  has(spoilt([](ordered_json& d) { d["stages"]["outlier_removal"]["accelerator"]["cycles"] = -4; }),
      "stage 'outlier_removal': accelerator: 'cycles'");
  has(spoilt([](ordered_json& d) { d["transform"][3].erase(3); }), "'transform' is not a 4x4 matrix");
  has(spoilt([](ordered_json& d) { d["transform"][0][0] = nullptr; }), "'transform' is not a 4x4 matrix");
  has(spoilt([](ordered_json& d) { d["transform"] = nullptr; }), "only a degenerate registration");
  has(spoilt([](ordered_json& d) { d["status"] = "degenerate"; }), "a degenerate registration has no 'transform'");
  has(spoilt([](ordered_json& d) { d["version"] = Report::kVersion + 1; }), "'version' is 2");
  has(spoilt([](ordered_json& d) { d["accelerator"]["fallback_searches"] = -1; }),
      "accelerator: 'fallback_searches' is not a count");
  has(spoilt([](ordered_json& d) { d["accelerator"]["job_list"] = 5; }), "'job_list'");
  has(spoilt([](ordered_json& d) { d["ground_truth"]["transform"] = "I"; }), "'ground_truth.transform'");
}
