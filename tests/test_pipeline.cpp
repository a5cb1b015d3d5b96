// The registration pipeline (registration/pipeline.hpp): pose recovery on the synthetic
// pair with both presets and every back-end, approximate search with thd 0 equal to exact,
// configuration errors, error injection (K-th neighbour, shell) reaching only its stages, and the
// KITTI ground-truth conversion (skipped without ../shared/data).
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include "registration/pipeline.hpp"
#include "workloads/io/cloud_io.hpp"
#include "workloads/pose.hpp"
#include "workloads/synthetic.hpp"

using namespace tigris;
using namespace tigris::registration;
namespace fs = std::filesystem;

namespace {

struct Pair {
  PointCloud source, target;  // frame 1 (later), frame 0 (earlier)
  Pose truth;                 // target <- source
};

// The synthetic pair; `azimuth_steps` below the default 1800 thins every ring (a faster test).
const Pair& synthetic(int azimuth_steps = 1800) {
  static std::map<int, Pair> cache;
  auto it = cache.find(azimuth_steps);
  if (it != cache.end()) return it->second;
  SyntheticConfig sc;
  sc.azimuth_steps = azimuth_steps;
  const SyntheticPair p = make_synthetic_pair(sc);
  Pair out{p.frame1, p.frame0, Pose::Identity()};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out.truth(r, c) = p.frame1_to_frame0[static_cast<std::size_t>(4 * r + c)];
  return cache.emplace(azimuth_steps, out).first->second;
}

const StageReport& stage(const RegistrationResult& r, const std::string& name) {
  for (const auto& s : r.stages)
    if (s.name == name) return s;
  FAIL("no stage " << name);
  throw std::logic_error("unreachable");
}

std::string temp_file(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("tigris_test_pipeline_" + name);
  std::ofstream(p) << text;
  return p.string();
}

}  // namespace

TEST_CASE("pipeline: DP4 recovers the synthetic pair's pose, every 3D search on the plug-in", "[pipeline]") {
  const Pair& p = synthetic();
  const RegistrationResult r = register_clouds(p.source, p.target, preset("dp4"));
  const PoseError e = pose_error(p.truth, r.transform);
  INFO("translation " << e.translation_m << " m, rotation " << e.rotation_deg << " deg");
  // Measured: 7.1 mm, 0.021 deg.
  CHECK(e.translation_m < 0.02);
  CHECK(e.rotation_deg < 0.05);
  std::vector<std::string> names;
  for (const auto& s : r.stages) names.push_back(s.name);
  CHECK(names ==
        std::vector<std::string>{"outlier_removal", "normals", "keypoints", "descriptors", "kpce", "rejection", "icp"});
  for (const char* searching : {"outlier_removal", "normals", "descriptors", "icp"}) {
    const StageReport& s = stage(r, searching);
    INFO(searching);
    CHECK(s.search == "exact");
    CHECK(s.kdtree.searches > 0);
    CHECK(s.kdtree.builds >= 2);
    CHECK(s.kdtree.visits.leaf_points > 0);
    CHECK(s.seconds >= s.kdtree.search_seconds);
  }
  CHECK(stage(r, "keypoints").search.empty());   // NARF: a range image, no KD-tree
  CHECK(stage(r, "kpce").kdtree.searches == 0);  // feature space, never the 3D plug-in
  CHECK(stage(r, "normals").kdtree.searches > 2 * 100000);
  CHECK(stage(r, "kpce").info["correspondences"].get<int>() >= 3);
  CHECK_FALSE(stage(r, "rejection").info["identity_fallback"].get<bool>());
  double sum = 0.0;
  for (const auto& s : r.stages) sum += s.seconds;
  CHECK(sum <= r.total_seconds + 1e-6);
}

TEST_CASE("pipeline: DP7 recovers the synthetic pair's pose", "[pipeline]") {
  // DP7 on the full pair takes ~16 s here: the test thins the rings to half the points.
  const Pair& p = synthetic(900);
  const RegistrationResult r = register_clouds(p.source, p.target, preset("dp7"));
  const PoseError e = pose_error(p.truth, r.transform);
  INFO("translation " << e.translation_m << " m, rotation " << e.rotation_deg << " deg");
  // Measured: 0.6 mm, 0.004 deg (1.4 mm, 0.0013 deg on the full pair).
  CHECK(e.translation_m < 0.005);
  CHECK(e.rotation_deg < 0.02);
  CHECK(stage(r, "keypoints").search == "exact");  // Harris3D searches the plug-in
  CHECK(stage(r, "keypoints").kdtree.searches > 0);
  CHECK(stage(r, "icp").info["iterations"].get<int>() >= 1);
}

TEST_CASE("pipeline: flann, exact and approx back-ends all register the pair", "[pipeline]") {
  const Pair& p = synthetic(900);
  for (const char* backend : {"flann", "exact", "approx"}) {
    PipelineConfig c = preset("dp4");
    c.search.backend = parse_backend(backend);
    const RegistrationResult r = register_clouds(p.source, p.target, c);
    const PoseError e = pose_error(p.truth, r.transform);
    INFO(backend << ": translation " << e.translation_m << " m, rotation " << e.rotation_deg << " deg");
    // Measured: flann and exact 10.1 mm, 0.032 deg (the same neighbours); approx 6.8 mm, 0.033 deg.
    CHECK(e.translation_m < 0.03);
    CHECK(e.rotation_deg < 0.1);
    const StageReport& ne = stage(r, "normals");
    CHECK(ne.search == backend);
    CHECK(ne.kdtree.searches > 0);
    // Only the paper's approximated stages (normals, RPCE) search approximately.
    CHECK(stage(r, "outlier_removal").search == (std::string(backend) == "flann" ? "flann" : "exact"));
    if (std::string(backend) == "flann") CHECK(ne.kdtree.visits.leaf_points == 0);
    if (std::string(backend) == "approx") {
      CHECK(ne.kdtree.leaders.followers > 0);
      CHECK(stage(r, "icp").kdtree.leaders.followers > 0);
    }
  }
}

TEST_CASE("pipeline: approximate search with thresholds 0 gives the exact transform", "[pipeline]") {
  const Pair& p = synthetic(900);
  PipelineConfig exact = preset("dp4");
  PipelineConfig approx = exact;
  approx.search.backend = Backend::Approx;
  approx.search.nn_thd = 0.0;
  approx.search.radius_thd = 0.0;
  const RegistrationResult a = register_clouds(p.source, p.target, exact);
  const RegistrationResult b = register_clouds(p.source, p.target, approx);
  CHECK(a.transform == b.transform);
  CHECK(stage(b, "normals").kdtree.leaders.followers == 0);
  CHECK(stage(b, "icp").kdtree.searches == stage(a, "icp").kdtree.searches);
}

// DP4 on the thinned synthetic pair without injection, computed once (the injection tests
// compare against it; each stays under ~2.5 s).
static const RegistrationResult& uninjected_dp4() {
  static const RegistrationResult r = register_clouds(synthetic(900).source, synthetic(900).target, preset("dp4"));
  return r;
}

TEST_CASE("pipeline: error injection off (K = 1, no shell) gives the uninjected transform", "[pipeline]") {
  const Pair& p = synthetic(900);
  PipelineConfig off = preset("dp4");
  apply_set(off, "inject.rpce_kth=1");
  apply_set(off, "inject.normals_shell_inner=0");
  apply_set(off, "inject.normals_shell_outer=0");
  const RegistrationResult& a = uninjected_dp4();
  const RegistrationResult b = register_clouds(p.source, p.target, off);
  CHECK(a.transform == b.transform);
  CHECK_FALSE(stage(b, "icp").info.contains("injected"));
  CHECK_FALSE(stage(b, "normals").info.contains("injected"));
  CHECK(stage(b, "normals").kdtree.neighbors == stage(a, "normals").kdtree.neighbors);
}

TEST_CASE("pipeline: the injected K-th neighbour reaches RPCE only", "[pipeline]") {
  const Pair& p = synthetic(900);
  const RegistrationResult& base = uninjected_dp4();
  PipelineConfig kth = preset("dp4");
  kth.inject.rpce_kth = 8;
  const RegistrationResult k = register_clouds(p.source, p.target, kth);
  CHECK(k.transform != base.transform);
  CHECK(stage(k, "icp").info["injected"]["k"] == 8);
  // The stages before ICP are untouched (the same initial estimate and normals).
  CHECK(k.initial == base.initial);
  CHECK(stage(k, "normals").kdtree.neighbors == stage(base, "normals").kdtree.neighbors);
}

TEST_CASE("pipeline: the injected shell reaches normal estimation only", "[pipeline]") {
  const Pair& p = synthetic(900);
  const RegistrationResult& base = uninjected_dp4();
  PipelineConfig shell = preset("dp4");  // r = 0.30
  shell.inject.normals_shell_inner = 0.1;
  shell.inject.normals_shell_outer = 0.4;
  const RegistrationResult s = register_clouds(p.source, p.target, shell);
  const StageReport& ne = stage(s, "normals");
  CHECK(ne.info["injected"]["inner_m"] == 0.1);
  CHECK(ne.kdtree.neighbors != stage(base, "normals").kdtree.neighbors);
  CHECK(s.transform != base.transform);
  CHECK(stage(s, "outlier_removal").kdtree.neighbors == stage(base, "outlier_removal").kdtree.neighbors);
  CHECK_FALSE(stage(s, "icp").info.contains("injected"));
  const PoseError e = pose_error(p.truth, s.transform);
  CHECK(e.translation_m < 0.1);  // the paper: registration tolerates a shell around r
}

TEST_CASE("pipeline config: error injection values are checked, naming the keys", "[pipeline]") {
  PipelineConfig c = preset("dp4");
  CHECK_THROWS_WITH(apply_set(c, "inject.rpce_kth=0"),
                    Catch::Contains("'inject.rpce_kth' = 0 is out of range (1..100000)"));
  CHECK_THROWS_WITH(apply_set(c, "inject.rpce_kth=two"),
                    Catch::Contains("'inject.rpce_kth' must be an integer, got 'two'"));
  CHECK_THROWS_WITH(apply_set(c, "inject.normals_shell_inner=-0.1"),
                    Catch::Contains("'inject.normals_shell_inner' = -0.1 is out of range"));
  CHECK_NOTHROW(validate(c, "x"));
  c.inject.normals_shell_inner = 0.35;  // R1 >= r = 0.30
  c.inject.normals_shell_outer = 0.5;
  CHECK_THROWS_WITH(validate(c, "conf.json"), Catch::StartsWith("conf.json") &&
                                                  Catch::Contains("'inject.normals_shell_inner' < 'normals.radius'"));
  c.inject.normals_shell_inner = 0.1;
  c.inject.normals_shell_outer = 0.3;  // R2 <= r
  CHECK_THROWS_WITH(validate(c, "x"), Catch::Contains("got 0.1, 0.3, 0.3"));
  c.inject.normals_shell_inner = 0.0;  // only one of the pair set
  CHECK_THROWS_WITH(validate(c, "x"), Catch::Contains("R1 < r < R2"));
  c.inject.normals_shell_outer = 0.4;
  CHECK_NOTHROW(validate(c, "x"));
  c.search.backend = Backend::Approx;
  CHECK_THROWS_WITH(validate(c, "x"), Catch::Contains("needs 'search.backend' flann or exact"));
  c.inject.normals_shell_outer = 0.0;
  c.inject.rpce_kth = 2;
  CHECK_THROWS_WITH(register_clouds(synthetic(900).source, synthetic(900).target, c),
                    Catch::Contains("needs 'search.backend' flann or exact"));
  // The echo carries the injection and reads back.
  c.search.backend = Backend::Exact;
  PipelineConfig d = preset("dp7");
  apply_json(d, to_json(c), "echo");
  CHECK(d.inject.rpce_kth == 2);
  CHECK(to_json(c)["inject"]["rpce_kth"] == 2);
}

TEST_CASE("pipeline config: presets, file and --set errors name the key", "[pipeline]") {
  CHECK(preset("dp4").normals.radius == 0.30);
  CHECK(preset("dp7").normals.radius == 0.75);
  CHECK_THROWS_WITH(preset("dp5"), Catch::Contains("unknown preset 'dp5'"));
  PipelineConfig c = preset("dp4");
  CHECK_THROWS_WITH(apply_set(c, "icp.max_iteration=3"),
                    Catch::Contains("unknown key 'icp.max_iteration'") && Catch::Contains("icp.max_iterations"));
  CHECK_THROWS_WITH(apply_set(c, "normals.radius=-1"),
                    Catch::Contains("'normals.radius' = -1.0 is out of range (> 0, <= 100)"));
  CHECK_THROWS_WITH(apply_set(c, "icp.max_iterations=2.5"), Catch::Contains("'icp.max_iterations' must be an integer"));
  CHECK_THROWS_WITH(apply_set(c, "icp.solver=qr"),
                    Catch::Contains("'icp.solver' must be one of `svd`, `lm`, got \"qr\""));
  CHECK_THROWS_WITH(apply_set(c, "kpce.reciprocal=maybe"), Catch::Contains("'kpce.reciprocal' must be true"));
  CHECK_THROWS_WITH(apply_set(c, "normals"), Catch::Contains("expected key=value"));
  apply_set(c, "icp.max_iterations=30");
  CHECK(c.icp.max_iterations == 30);

  const std::string bad_key = temp_file("bad_key.json", R"({"icp": {"solver": "lm", "max_iter": 3}})");
  CHECK_THROWS_WITH(apply_file(c, bad_key),
                    Catch::StartsWith(bad_key) && Catch::Contains("unknown key 'icp.max_iter'"));
  const std::string bad_value = temp_file("bad_value.json", R"({"search": {"top_height": 31}})");
  CHECK_THROWS_WITH(apply_file(c, bad_value), Catch::Contains("'search.top_height' = 31 is out of range"));
  const std::string bad_type = temp_file("bad_type.json", R"({"descriptors": {"radius": "big"}})");
  CHECK_THROWS_WITH(apply_file(c, bad_type), Catch::Contains("'descriptors.radius' must be a number"));
  const std::string block = temp_file("block.json", R"({"icp": 3})");
  CHECK_THROWS_WITH(apply_file(c, block), Catch::Contains("'icp' is a block"));
  const std::string garbage = temp_file("garbage.json", "{ not json");
  CHECK_THROWS_WITH(apply_file(c, garbage), Catch::StartsWith(garbage) && Catch::Contains(": JSON parse error"));
  CHECK_THROWS_WITH(apply_file(c, "/nonexistent/pipeline.json"),
                    Catch::Contains("/nonexistent/pipeline.json: cannot read configuration file: no such file"));
  // The same error quality as the accelerator's configuration.
  const std::string twice = temp_file("twice.json", R"({"icp": {"max_iterations": 5}, "icp": {"reciprocal": true}})");
  CHECK_THROWS_WITH(apply_file(c, twice), Catch::StartsWith(twice) && Catch::Contains("key 'icp' appears twice"));
  const std::string overflow = temp_file("overflow.json", R"({"normals": {"radius": 1e400}})");
  CHECK_THROWS_WITH(apply_file(c, overflow), Catch::StartsWith(overflow) && Catch::Contains("number overflow"));
  const std::string object = temp_file("object.json", R"({"normals": {"radius": {"v": 1}}})");
  CHECK_THROWS_WITH(apply_file(c, object), Catch::Contains("'normals.radius' must be a number, got an object"));
  const std::string ten = temp_file("ten.json", R"({"icp": {"max_iterations": 10.0}})");
  CHECK_THROWS_WITH(apply_file(c, ten), Catch::Contains("must be an integer, got 10.0"));
  const std::string nul = temp_file("nul.json", "{\"icp\": {\"max\\u0000it\": 1}}");
  CHECK_THROWS_WITH(apply_file(c, nul), Catch::Contains("unknown key 'icp.max\\x00it'"));
  CHECK_THROWS_WITH(apply_file(c, "/tmp"), Catch::Contains("/tmp: cannot read configuration file: is a folder"));
  apply_set(c, "icp.transformation_epsilon=1e-320");  // subnormal: a number, in range
  CHECK(c.icp.transformation_epsilon > 0.0);
  CHECK_THROWS_WITH(apply_set(c, "search.nn_thd=1e9", "--approx-thd"),
                    Catch::StartsWith("--approx-thd (search.nn_thd=1e9)") && Catch::Contains("out of range"));

  // The echo reads back to the same configuration; comments and dotted keys are accepted.
  PipelineConfig d = preset("dp7");
  apply_json(d, to_json(c), "echo");
  CHECK(to_json(d) == to_json(c));
  apply_json(d, nlohmann::json::parse(R"({"// note": "x", "icp": {"error": "point_to_point"}})"), "inline");
  CHECK(d.icp.error == IcpError::PointToPoint);
}

TEST_CASE("poses: files, KITTI camera poses to the Velodyne frame, relative pose error", "[pipeline]") {
  const std::string p44 = temp_file("p44.txt", "1 0 0 1\n0 1 0 2\n0 0 1 3\n0 0 0 1\n");
  const std::string p34 = temp_file("p34.txt", "1,0,0,1, 0,1,0,2, 0,0,1,3");
  CHECK(read_pose_file(p44) == read_pose_file(p34));
  CHECK(read_pose_file(p44)(1, 3) == 2.0);
  CHECK_THROWS_WITH(read_pose_file(temp_file("p5.txt", "1 2 3 4 5")), Catch::Contains("found 5 numbers"));
  CHECK_THROWS_WITH(read_pose_file(temp_file("pnan.txt", "1 0 0 x 0 1 0 0 0 0 1 0")), Catch::Contains("'x' is not"));
  CHECK_THROWS_WITH(read_pose_file(temp_file("pskew.txt", "2 0 0 0 0 1 0 0 0 0 1 0")), Catch::Contains("not a rigid"));
  CHECK_THROWS_WITH(read_pose_file("/nonexistent/pose.txt"),
                    Catch::Contains("/nonexistent/pose.txt: cannot read the pose file: no such file"));

  // E = inv(T_gt) * T_est: 2 cm and 0.1 degree off a 1 m move.
  Pose gt = Pose::Identity();
  gt(0, 3) = 1.0;
  Pose est = gt;
  est(1, 3) = 0.02;
  const double a = 0.1 * M_PI / 180.0;
  est.topLeftCorner<2, 2>() << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  const PoseError e = pose_error(gt, est);
  CHECK(e.translation_m == Approx(0.02).margin(1e-9));
  CHECK(e.rotation_deg == Approx(0.1).epsilon(1e-6));
  CHECK(e.rotation_deg_per_m == Approx(0.1).epsilon(1e-6));

  // Camera forward (z) is Velodyne forward (x); camera right (x) is Velodyne -y.
  Pose cam = Pose::Identity();
  cam(2, 3) = 0.5;
  cam(0, 3) = 0.1;
  const Pose velo = kitti_relative_velo_pose(cam, Pose::Identity());
  CHECK(velo(0, 3) == Approx(0.5));
  CHECK(velo(1, 3) == Approx(-0.1));
  CHECK(velo(2, 3) == Approx(0.0).margin(1e-12));
}

TEST_CASE("KITTI 00: frame 1 in frame 0 moves about 0.86 m forward, and DP4 registers it", "[pipeline][kitti]") {
  const std::string dir = std::string(TIGRIS_DATA_DIR) + "/kitti-00";
  if (!fs::is_directory(dir)) {
    WARN("KITTI data not found at " << dir
                                    << ": skipping this test (configure with "
                                       "-DTIGRIS_DATA_DIR=<folder with kitti-00/> to run it)");
    return;
  }
  const Pose gt = kitti_relative_velo_pose(dir + "/poses.txt", 1, 0);
  CHECK(gt(0, 3) == Approx(0.86).margin(0.01));  // forward
  CHECK(std::abs(gt(1, 3)) < 0.1);
  CHECK(std::abs(gt(2, 3)) < 0.1);
  CHECK(rotation_angle_deg(gt) < 0.5);
  CHECK_THROWS_WITH(kitti_relative_velo_pose(dir + "/poses.txt", 9, 0), Catch::Contains("poses 0..5"));

  const RegistrationResult r =
      register_clouds(load_cloud(dir + "/000001.bin"), load_cloud(dir + "/000000.bin"), preset("dp4"));
  const PoseError e = pose_error(gt, r.transform);
  INFO("translation " << e.translation_m << " m, rotation " << e.rotation_deg << " deg, estimate x "
                      << r.transform(0, 3));
  // Measured 0.18 m and 0.2 deg: every configuration tried converges to 0.68 m forward, not 0.86
  // (docs/registration.md, "Decisions"); these bounds catch a broken pipeline, not that shortfall.
  CHECK(e.translation_m < 0.3);
  CHECK(e.rotation_deg < 0.5);
  CHECK(r.transform(0, 3) > 0.5);
}

// The accelerator in the loop with a port that answers each job with the golden
// model in this process: the batching itself, without SystemC. Each job is searched in its
// order, so the approximate leader state evolves as on the CPU and every back-end must give
// the CPU's transform bit for bit; the announced stages batch every search (key points by
// Harris may fall back in refinement).
namespace {
class GoldenPort : public AcceleratorPort {
 public:
  AccelAnswer run(const AccelJob& job) override {
    const KdTree tree = build_kdtree(*job.points, job.top_height);
    AccelAnswer a;
    a.results = search(tree, *job.queries, job.params).results;
    a.cycles = job.queries->size();  // one per query: a count the test can check
    a.search_seconds = 1e-9 * static_cast<double>(job.queries->size());
    ++jobs;
    if (job.tree_id == 0) ++zero_ids;
    if (prefetched && same(job, *prefetched, prefetched_queries)) {
      ++prefetches_taken;
      prefetched.reset();
    }
    return a;
  }
  // A prefetched job must be one the stage runs later (here: after the source's).
  void prefetch(const AccelJob& job) override {
    ++prefetches;
    prefetched = job;
    prefetched_queries = *job.queries;
  }
  int jobs = 0, zero_ids = 0, prefetches = 0, prefetches_taken = 0;

 private:
  static bool same(const AccelJob& a, const AccelJob& b, const PointCloud& b_queries) {
    return same_search(a.params, b.params) && a.tree_id == b.tree_id && a.top_height == b.top_height &&
           a.queries->size() == b_queries.size() &&
           std::equal(a.queries->begin(), a.queries->end(), b_queries.begin(),
                      [](const Point3& x, const Point3& y) { return x.x == y.x && x.y == y.y && x.z == y.z; });
  }
  std::optional<AccelJob> prefetched;
  PointCloud prefetched_queries;
};
}  // namespace

TEST_CASE("pipeline: the accelerator in the loop batches the announced stages and gives the CPU's transform",
          "[pipeline][accel]") {
  const Pair& p = synthetic(900);
  for (const char* preset_name : {"dp4", "dp7"}) {
    for (const char* backend : {"exact", "approx"}) {
      INFO(preset_name << " " << backend);
      PipelineConfig c = preset(preset_name);
      c.search.backend = parse_backend(backend);
      const RegistrationResult cpu = register_clouds(p.source, p.target, c);
      auto port = std::make_shared<GoldenPort>();
      PipelineHooks hooks;
      hooks.accelerator = port;
      const RegistrationResult loop = register_clouds(p.source, p.target, c, hooks);
      CHECK(loop.transform == cpu.transform);
      CHECK(port->zero_ids == 0);
      std::uint64_t jobs = 0;
      for (const StageReport& s : loop.stages) {
        INFO(s.name);
        const auto& a = s.kdtree.accel;
        jobs += a.jobs;
        CHECK(a.queries + a.fallback_searches == s.kdtree.searches);  // every search is one or the other
        CHECK(a.cycles == a.queries);
        if (s.name == "outlier_removal" || s.name == "normals" || s.name == "icp" || s.name == "descriptors") {
          CHECK(a.fallback_searches == 0);
          CHECK(a.jobs >= 2);  // both clouds; ICP: one (or two when reciprocal) per iteration
        }
      }
      CHECK(jobs == static_cast<std::uint64_t>(port->jobs));
      // The target's outlier-removal and normals jobs are handed over early, each exactly the job
      // run next (so a port may run it beside the source's).
      CHECK(port->prefetches == 2);
      CHECK(port->prefetches_taken == port->prefetches);
      const auto& icp = stage(loop, "icp");
      const int per_iteration = c.icp.reciprocal ? 2 : 1;
      CHECK(icp.kdtree.accel.jobs == static_cast<std::uint64_t>(per_iteration * icp.info["iterations"].get<int>()));
    }
  }
  PipelineConfig flann = preset("dp4");
  flann.search.backend = Backend::Flann;
  PipelineHooks hooks;
  hooks.accelerator = std::make_shared<GoldenPort>();
  CHECK_THROWS_WITH(register_clouds(p.source, p.target, flann, hooks), Catch::Contains("not flann"));
}
