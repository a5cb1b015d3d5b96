// Registers a source cloud onto a target cloud with a plain PCL ICP whose search method is the
// Tigris back-end (tigris::registration::TigrisKdTree), and prints the transform and what the
// searches cost. With --accel, each ICP iteration's searches run as one job on the accelerator
// model (checked against the golden model), and the modeled KD-tree time is printed.
//
//   register_pair SOURCE TARGET [--accel] [--approx] [--config PRESET|FILE] [--record-trace FILE]
//   register_pair --builtin ...   the built-in synthetic pair (frames 0 and 1)
//
// SOURCE and TARGET: KITTI .bin, .pcd or .ply.
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <pcl/common/transforms.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>

#include "registration/search_plugin.hpp"
#include "registration/trace_recorder.hpp"
#include "testbench/accel_in_loop.hpp"
#include "testbench/config.hpp"
#include "testbench/presets.hpp"
#include "traces/workload_trace.hpp"
#include "workloads/io/cloud_io.hpp"
#include "workloads/workload.hpp"

using Point = pcl::PointXYZ;
using Cloud = pcl::PointCloud<Point>;
namespace reg = tigris::registration;

namespace {

struct Args {
  std::string source, target, config, record_trace;
  bool builtin = false, accel = false, approx = false;
};

Args parse(int argc, char** argv) {
  Args a;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string w = argv[i];
    const bool has_value = i + 1 < argc;
    if (w == "--builtin")
      a.builtin = true;
    else if (w == "--accel")
      a.accel = true;
    else if (w == "--approx")
      a.approx = true;
    else if (w == "--config" && has_value)
      a.config = argv[++i];
    else if (w == "--record-trace" && has_value)
      a.record_trace = argv[++i];
    else if (w.rfind("--", 0) == 0)
      throw std::invalid_argument("unknown flag or missing value: " + w);
    else
      files.push_back(w);
  }
  if (a.builtin == !files.empty() || (!a.builtin && files.size() != 2))
    throw std::invalid_argument("give SOURCE and TARGET cloud files, or --builtin");
  if (!a.builtin) a.source = files[0], a.target = files[1];
  if (!a.config.empty() && !a.accel) throw std::invalid_argument("--config configures the accelerator: add --accel");
  // A trace holds the CPU's search times; in the loop they would include the simulations.
  if (!a.record_trace.empty() && a.accel)
    throw std::invalid_argument("--record-trace records the CPU's searches: not with --accel");
  return a;
}

// A Tigris cloud as PCL's, thinned by a 0.3 m voxel grid (ICP's usual input).
Cloud::Ptr to_pcl(const tigris::PointCloud& in) {
  auto full = std::make_shared<Cloud>();
  for (const tigris::Point3& p : in) full->push_back(Point(p.x, p.y, p.z));
  auto out = std::make_shared<Cloud>();
  pcl::VoxelGrid<Point> grid;
  grid.setInputCloud(full);
  grid.setLeafSize(0.3f, 0.3f, 0.3f);
  grid.filter(*out);
  return out;
}

int run(const Args& a) {
  tigris::Workload w = a.builtin ? tigris::load_workload("", "", 1) : tigris::Workload{};
  if (!a.builtin) w.queries = tigris::load_cloud(a.source), w.cloud = tigris::load_cloud(a.target);
  const Cloud::Ptr source = to_pcl(w.queries), target = to_pcl(w.cloud);

  // The back-end: the golden model (exact or approximate) and, with --accel, the model in the
  // loop. Make the model server before the searching starts (accel_in_loop.hpp says why).
  reg::SearchSettings settings;
  settings.backend = a.approx ? reg::Backend::Approx : reg::Backend::Exact;
  if (a.accel) {
    tigris::hw::AcceleratorConfig cfg;
    if (!a.config.empty()) tigris::apply_config_file(cfg, tigris::config_path(a.config, TIGRIS_PRESETS_DIR));
    tigris::validate_config(cfg);
    settings.accelerator = std::make_shared<tigris::ModelInTheLoop>(cfg, tigris::WorkLimits{}, 1);
  }
  if (!a.record_trace.empty()) settings.recorder = std::make_shared<reg::TraceRecorder>();
  auto counters = std::make_shared<reg::SearchCounters>();
  auto tree = std::make_shared<reg::TigrisKdTree<Point>>(settings, counters);

  pcl::IterativeClosestPoint<Point, Point> icp;
  icp.setInputSource(source);
  icp.setInputTarget(target);
  icp.setSearchMethodTarget(tree);
  icp.setMaxCorrespondenceDistance(1.0);
  icp.setMaximumIterations(30);
  icp.setTransformationEpsilon(1e-8);
  // Each iteration searches every (transformed) source point in order: announce them, so the
  // back-end runs them as one accelerator job. ICP's callback hands over the next iteration's.
  tree->expect_queries(*source);
  std::function<void(const Cloud&, const pcl::Indices&, const Cloud&, const pcl::Indices&)> next =
      [&](const Cloud& moved, const pcl::Indices&, const Cloud&, const pcl::Indices&) {
        tree->expect_queries(moved);
        if (settings.recorder) settings.recorder->next_iteration();
      };
  icp.registerVisualizationCallback(next);
  if (settings.recorder) settings.recorder->begin_stage("icp");
  Cloud aligned;
  icp.align(aligned);
  // The fitness score searches the source once more, moved as getFitnessScore moves it (not
  // bit for bit align()'s output): announce those points, so they are a job too.
  Cloud final_source;
  pcl::transformPointCloud(*source, final_source, icp.getFinalTransformation());
  tree->expect_queries(final_source);
  const double fitness = icp.getFitnessScore();

  std::printf("source %zu points, target %zu points (after a 0.3 m voxel grid)\n", source->size(), target->size());
  std::printf("ICP %s after %d iterations, fitness %.6f\ntransform:\n",
              icp.hasConverged() ? "converged" : "did not converge", icp.nr_iterations_, fitness);
  const Eigen::Matrix4f t = icp.getFinalTransformation();
  for (int r = 0; r < 4; ++r) std::printf("  %10.6f %10.6f %10.6f %10.6f\n", t(r, 0), t(r, 1), t(r, 2), t(r, 3));
  const reg::SearchCounters& c = *counters;
  std::printf("searches %llu, neighbours %llu, tree builds %llu, search %.3f s (CPU)\n",
              static_cast<unsigned long long>(c.searches), static_cast<unsigned long long>(c.neighbors),
              static_cast<unsigned long long>(c.builds), c.search_seconds);
  const tigris::VisitTotals& v = a.accel ? c.accel.visits : c.visits;  // in the loop: the accelerator's
  std::printf("visits%s: %llu top-tree nodes, %llu leaf points\n", a.accel ? " (accelerator)" : "",
              static_cast<unsigned long long>(v.top), static_cast<unsigned long long>(v.leaf_points));
  if (a.accel)
    std::printf(
        "accelerator: %llu jobs, %llu queries, %llu cycles, modeled KD-tree time %.6f s (+ host link %.6f s), "
        "%.1f uJ; %llu searches fell back to the CPU\n",
        static_cast<unsigned long long>(c.accel.jobs), static_cast<unsigned long long>(c.accel.queries),
        static_cast<unsigned long long>(c.accel.cycles), c.accel.modeled_search_seconds, c.accel.modeled_host_seconds,
        c.accel.energy_pj * 1e-6, static_cast<unsigned long long>(c.accel.fallback_searches));
  if (settings.recorder) {
    tigris::trace::Trace tr = settings.recorder->finish();
    tr.meta = {{"tool", "examples/pcl_search"}, {"search", a.approx ? "approx" : "exact"}};
    tr.stages.push_back({"icp", c.search_seconds, c.search_seconds, c.build_seconds});
    tr.total_seconds = c.search_seconds;
    const std::vector<std::uint8_t> bytes = tigris::trace::encode(tr);
    std::ofstream(a.record_trace, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    std::printf("trace %s: %zu jobs (tigris run --trace %s)\n", a.record_trace.c_str(), tr.jobs.size(),
                a.record_trace.c_str());
  }
  return icp.hasConverged() ? 0 : 1;
}

}  // namespace

// SystemC's library wants an sc_main; the model runs from this plain main() (each job in a
// process of the model server's), so it is never called.
extern "C" int sc_main(int, char**) { return 2; }

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "register_pair: error: %s\n", e.what());
    return 2;
  }
}
