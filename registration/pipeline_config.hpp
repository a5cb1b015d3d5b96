// The registration pipeline's configuration (docs/registration.md): one JSON document nested by
// stage, every key typed and declared once in visit() with its unit, range and meaning. Files,
// --set, the dump, the reference and their errors are the accelerator's configuration's own
// (config/apply.hpp). Two presets: `dp4` (performance-oriented) and `dp7` (accuracy-oriented),
// after the paper's design points.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "config/spec.hpp"
#include "sw_ref/leader_policy.hpp"

namespace tigris::registration {

// The 3D KD-tree search behind every PCL search of the pipeline (search_plugin.hpp).
enum class Backend { Flann, Exact, Approx };
const char* to_string(Backend backend);          // "flann" | "exact" | "approx"
Backend parse_backend(const std::string& name);  // throws std::invalid_argument naming the choices

enum class KeypointMethod { Narf, Harris3d, Sift };
enum class DescriptorMethod { Fpfh, Shot };
enum class RejectionMethod { Ransac, Distance };
enum class IcpError { PointToPoint, PointToPlane };
enum class IcpSolver { Svd, Lm };
const char* to_string(KeypointMethod m);
const char* to_string(DescriptorMethod m);
const char* to_string(RejectionMethod m);
const char* to_string(IcpError e);
const char* to_string(IcpSolver s);

struct PipelineConfig {
  struct {
    bool enabled = true;
    int mean_k = 50;
    double stddev_mul = 1.0;
  } outlier_removal;
  struct {
    double radius = 0.30;
  } normals;
  struct {
    KeypointMethod method = KeypointMethod::Narf;
    struct {
      double angular_resolution_deg = 0.5, support_size = 0.2;
    } narf;
    struct {
      double radius = 0.35, threshold = 0.01;
      bool non_max_suppression = true, refine = true;
    } harris3d;
    struct {
      double min_scale = 0.03;
      int octaves = 8, scales_per_octave = 12;
      double min_contrast = 0.08;
    } sift;
  } keypoints;
  struct {
    DescriptorMethod method = DescriptorMethod::Fpfh;
    double radius = 0.85;
  } descriptors;
  struct {
    bool reciprocal = true;
  } kpce;
  struct {
    RejectionMethod method = RejectionMethod::Ransac;
    double ransac_threshold = 0.2;
    int ransac_iterations = 10000;
    double distance_max = 2.0;
  } rejection;
  struct {
    IcpError error = IcpError::PointToPoint;
    IcpSolver solver = IcpSolver::Svd;
    int max_iterations = 15;
    double max_correspondence_distance = 1.2;
    double transformation_epsilon = 1e-9;
    double euclidean_fitness_epsilon = 1e-6;
    bool reciprocal = true;
    bool ransac = true;
    double ransac_threshold = 1.2;
    int ransac_iterations = 100;
  } icp;
  struct {
    Backend backend = Backend::Exact;
    int top_height = 10;
    int normals_leaf_size = 0;  // 0: top_height
    int rpce_leaf_size = 0;
    double nn_thd = 1.2;
    double radius_thd = 0.4;
    int leader_capacity = 16;
    int leader_width = 0;
    LeaderScope leader_scope = LeaderScope::FirstLeaf;
    LeaderInFlight leader_in_flight = LeaderInFlight::Wait;
  } search;
  // Error injection (the paper's Figure 5; injection.hpp has the exact semantics). Exact
  // back-ends only (flann, exact); off by default.
  struct {
    int rpce_kth = 1;
    double normals_shell_inner = 0.0;
    double normals_shell_outer = 0.0;
  } inject;

  // Every key with its unit, allowed values and meaning, in file order: the one configuration
  // mechanism the accelerator's configuration uses too (config/key_table.hpp).
  static constexpr const char* kListCommand = "tigris register --list-config";
  static constexpr const char* kSetExample = "normals.radius=0.5";
  template <class V>
  void visit(V&& v) {
    using namespace tigris::config;
    v("outlier_removal.enabled", outlier_removal.enabled, {"-", boolean(), "run statistical outlier removal first"});
    v("outlier_removal.mean_k", outlier_removal.mean_k, {"points", in(1, 1000), "neighbours averaged per point"});
    v("outlier_removal.stddev_mul", outlier_removal.stddev_mul,
      {"-", in(0, 100), "keep points whose mean neighbour distance is within mean + stddev_mul * sigma"});
    v("normals.radius", normals.radius, {"m", above(0, 100), "normal estimation search radius"});
    v("keypoints.method", keypoints.method,
      {"-", one_of({KeypointMethod::Narf, KeypointMethod::Harris3d, KeypointMethod::Sift}), "key-point detector"});
    v("keypoints.narf.angular_resolution_deg", keypoints.narf.angular_resolution_deg,
      {"deg", above(0, 10), "range-image angular resolution"});
    v("keypoints.narf.support_size", keypoints.narf.support_size, {"m", above(0, 100), "NARF support size"});
    v("keypoints.harris3d.radius", keypoints.harris3d.radius, {"m", above(0, 100), "Harris3D neighbourhood radius"});
    v("keypoints.harris3d.threshold", keypoints.harris3d.threshold, {"-", in(0, 1e6), "Harris3D response threshold"});
    v("keypoints.harris3d.non_max_suppression", keypoints.harris3d.non_max_suppression,
      {"-", boolean(), "Harris3D non-maximum suppression"});
    v("keypoints.harris3d.refine", keypoints.harris3d.refine, {"-", boolean(), "Harris3D corner refinement"});
    v("keypoints.sift.min_scale", keypoints.sift.min_scale, {"m", above(0, 100), "SIFT smallest scale"});
    v("keypoints.sift.octaves", keypoints.sift.octaves, {"octaves", in(1, 16), "SIFT octaves"});
    v("keypoints.sift.scales_per_octave", keypoints.sift.scales_per_octave,
      {"scales", in(1, 64), "SIFT scales per octave"});
    v("keypoints.sift.min_contrast", keypoints.sift.min_contrast, {"-", in(0, 1e6), "SIFT minimum contrast"});
    v("descriptors.method", descriptors.method,
      {"-", one_of({DescriptorMethod::Fpfh, DescriptorMethod::Shot}), "feature descriptor"});
    v("descriptors.radius", descriptors.radius, {"m", above(0, 100), "descriptor search radius"});
    v("kpce.reciprocal", kpce.reciprocal,
      {"-", boolean(), "key-point correspondences must be mutual nearest features"});
    v("rejection.method", rejection.method,
      {"-", one_of({RejectionMethod::Ransac, RejectionMethod::Distance}), "key-point correspondence rejection"});
    v("rejection.ransac_threshold", rejection.ransac_threshold, {"m", above(0, 100), "RANSAC inlier threshold"});
    v("rejection.ransac_iterations", rejection.ransac_iterations, {"iterations", in(1, 10000000), "RANSAC iterations"});
    v("rejection.distance_max", rejection.distance_max,
      {"m", above(0, 1000), "distance rejection: largest key-point pair distance kept"});
    v("icp.error", icp.error, {"-", one_of({IcpError::PointToPoint, IcpError::PointToPlane}), "ICP error metric"});
    v("icp.solver", icp.solver,
      {"-", one_of({IcpSolver::Svd, IcpSolver::Lm}), "ICP solver (svd with point_to_plane: linear least squares)"});
    v("icp.max_iterations", icp.max_iterations, {"iterations", in(1, 10000), "ICP iterations at most"});
    v("icp.max_correspondence_distance", icp.max_correspondence_distance,
      {"m", above(0, 1000), "RPCE drops pairs farther apart"});
    v("icp.transformation_epsilon", icp.transformation_epsilon,
      {"-", in(0, 1), "ICP stops when the step is below this"});
    v("icp.euclidean_fitness_epsilon", icp.euclidean_fitness_epsilon,
      {"m^2", in(0, 1e6), "ICP stops when the relative MSE change is below this"});
    v("icp.reciprocal", icp.reciprocal,
      {"-", boolean(), "RPCE keeps mutual nearest neighbours only (searches both ways)"});
    v("icp.ransac", icp.ransac, {"-", boolean(), "ICP-internal RANSAC correspondence rejector"});
    v("icp.ransac_threshold", icp.ransac_threshold, {"m", above(0, 1000), "ICP-internal RANSAC inlier threshold"});
    v("icp.ransac_iterations", icp.ransac_iterations,
      {"iterations", in(1, 10000000), "ICP-internal RANSAC iterations"});
    v("search.backend", search.backend,
      {"-", one_of({Backend::Flann, Backend::Exact, Backend::Approx}),
       "3D KD-tree search: PCL's FLANN (CPU baseline), golden exact, golden approximate"});
    v("search.top_height", search.top_height,
      {"levels", in(0, 30), "top-tree height (clamped to each cloud's full height)"});
    v("search.normals_leaf_size", search.normals_leaf_size,
      {"points", in(0, 1 << 30),
       "normal estimation's trees: the lowest top height whose leaf sets hold at most this many points, "
       "instead of top_height (0: top_height; the paper authors' pipeline: 64, bin/config.txt)"});
    v("search.rpce_leaf_size", search.rpce_leaf_size,
      {"points", in(0, 1 << 30),
       "RPCE's (ICP's) trees: as normals_leaf_size (0: top_height; the authors' pipeline: 32)"});
    v("search.nn_thd", search.nn_thd, {"m", in(0, 1000), "approximate NN/kNN leader threshold"});
    v("search.radius_thd", search.radius_thd, {"fraction of r", in(0, 1), "approximate radius threshold"});
    v("search.leader_capacity", search.leader_capacity,
      {"leaders", in(1, 1 << 20), "leaders kept per leaf (approximate)"});
    v("search.leader_width", search.leader_width,
      {"results", in(0, 1 << 20), "leader result width R for NN/kNN (0: k; every_leaf only)"});
    v("search.leader_scope", search.leader_scope,
      {"-", one_of({LeaderScope::FirstLeaf, LeaderScope::EveryLeaf}),
       "approximate: where leaders are checked: first_leaf (the paper authors' code) or every_leaf"});
    v("search.leader_in_flight", search.leader_in_flight,
      {"-", one_of({LeaderInFlight::Wait, LeaderInFlight::FinishedOnly}),
       "approximate, first_leaf, accelerator in the loop: wait or finished_only (the CPU runs its "
       "searches one by one, where the two agree)"});
    v("inject.rpce_kth", inject.rpce_kth,
      {"rank", in(1, 100000), "error injection: RPCE's NN searches return the K-th nearest (1: off; --inject-kth)"});
    v("inject.normals_shell_inner", inject.normals_shell_inner,
      {"m", in(0, 100), "error injection: normals' radius searches return R1 <= d <= R2, this is R1 (--inject-shell)"});
    v("inject.normals_shell_outer", inject.normals_shell_outer,
      {"m", in(0, 100), "error injection: R2, R1 < normals.radius < R2; both 0: off"});
  }
};

// The preset names, and a preset's configuration (throws std::invalid_argument naming the
// preset and the choices).
const std::vector<std::string>& preset_names();
PipelineConfig preset(const std::string& name);

// Applies a JSON object (nested by stage, or dotted keys at any level; keys starting with "//"
// are comments), a file (// and /* */ comments allowed) or one `key=value` (as given to --set,
// or by `flag` when a flag sets the key: errors then start with "flag (key=value)"). Every key is checked; errors are
// std::invalid_argument starting with the source and naming the key: unknown key (with the nearest valid name), wrong
// type, out of range, or not one of the allowed names (config/apply.hpp).
void apply_json(PipelineConfig& config, const nlohmann::json& doc, const std::string& source);
void apply_file(PipelineConfig& config, const std::string& path);
void apply_set(PipelineConfig& config, const std::string& assignment, const std::string& flag = "");
// The checks across keys, once every key is set (register_clouds calls it too): every key in
// range (for values set in code), the injected shell must satisfy inner < normals.radius < outer
// (or both 0), and injection needs an exact back-end. std::invalid_argument starting with
// `source` and naming the keys.
void validate(const PipelineConfig& config, const std::string& source);
// The full configuration as JSON, nested by stage (the file format; apply_json reads it back).
nlohmann::json to_json(const PipelineConfig& config);
// Every key with the given configuration's value: a Markdown table (`tigris register
// --list-config`, its value column headed `heading`) and JSON for tools (--json), in the
// accelerator's formats.
std::string key_reference(const PipelineConfig& config, const std::string& heading);
nlohmann::json key_reference_json(const PipelineConfig& config);

}  // namespace tigris::registration
