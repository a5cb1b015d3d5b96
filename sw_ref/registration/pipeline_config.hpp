// The registration pipeline's configuration (docs/registration.md): one JSON document nested by
// stage, every key typed, documented with its unit and range, unknown keys an error naming the
// key (the same style as the accelerator's configuration in testbench/config_*). Two presets:
// `dp4` (performance-oriented) and `dp7` (accuracy-oriented), after the paper's design points.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tigris::registration {

struct PipelineConfig {
  struct {
    bool enabled = true;
    int mean_k = 50;           // neighbours whose mean distance is scored
    double stddev_mul = 1.0;   // keep points within mean + stddev_mul * sigma
  } outlier_removal;
  struct {
    double radius = 0.30;      // m
  } normals;
  struct {
    std::string method = "narf";  // narf | harris3d | sift
    struct { double angular_resolution_deg = 0.5, support_size = 0.2; } narf;
    struct { double radius = 0.35, threshold = 0.01; bool non_max_suppression = true, refine = true; } harris3d;
    struct { double min_scale = 0.03; int octaves = 8, scales_per_octave = 12; double min_contrast = 0.08; } sift;
  } keypoints;
  struct {
    std::string method = "fpfh";  // fpfh | shot
    double radius = 0.85;         // m
  } descriptors;
  struct {
    bool reciprocal = true;
  } kpce;
  struct {
    std::string method = "ransac";  // ransac | distance
    double ransac_threshold = 0.2;  // m
    int ransac_iterations = 10000;
    double distance_max = 2.0;      // m, key-point pairs farther apart are rejected
  } rejection;
  struct {
    std::string error = "point_to_point";  // point_to_point | point_to_plane
    std::string solver = "svd";            // svd | lm
    int max_iterations = 15;
    double max_correspondence_distance = 1.2;  // m
    double transformation_epsilon = 1e-9;
    double euclidean_fitness_epsilon = 1e-6;
    bool reciprocal = true;
    bool ransac = true;                 // ICP-internal RANSAC correspondence rejector
    double ransac_threshold = 1.2;      // m
    int ransac_iterations = 100;
  } icp;
  struct {
    std::string backend = "exact";  // flann | exact | approx
    int top_height = 10;
    double nn_thd = 1.2;            // m, approximate NN (RPCE)
    double radius_thd = 0.4;        // fraction of r, approximate radius search (normals)
    int leader_capacity = 16;
    int leader_width = 0;
  } search;
  // Error injection (the paper's Figure 5; search_plugin.hpp has the exact semantics). Exact
  // back-ends only (flann, exact); off by default.
  struct {
    int rpce_kth = 1;                  // RPCE's NN searches return the K-th nearest (1: off)
    double normals_shell_inner = 0.0;  // m, R1: normal estimation's radius searches return
    double normals_shell_outer = 0.0;  // m, R2: R1 <= d <= R2 instead of d <= r (both 0: off)
  } inject;
};

// The preset names, and a preset's configuration (throws std::invalid_argument naming the
// preset and the choices).
const std::vector<std::string>& preset_names();
PipelineConfig preset(const std::string& name);

// Applies a JSON object (nested by stage, or dotted keys at any level; keys starting with "//"
// are comments). Every key is checked; errors are std::invalid_argument starting with
// `source` (the file name) and naming the key: unknown key (with the nearest valid name),
// wrong type, out of range, or not one of the allowed names.
void apply_json(PipelineConfig& config, const nlohmann::json& doc, const std::string& source);
// The checks across keys, once every key is set (register_clouds calls it too): the injected
// shell must satisfy inner < normals.radius < outer (or both 0), and injection needs an exact
// back-end. std::invalid_argument starting with `source` and naming the keys.
void validate(const PipelineConfig& config, const std::string& source);
// Reads a JSON file and applies it; errors name the file (missing, unreadable, invalid JSON).
void apply_file(PipelineConfig& config, const std::string& path);
// Applies `key=value` as given to --set (the value parsed per the key's type); errors start
// with "--set key=value", or with `flag` and the key when a flag sets the key.
void apply_set(PipelineConfig& config, const std::string& assignment, const std::string& flag = "");
// The full configuration as JSON, nested by stage (the file format; apply_json reads it back).
nlohmann::json to_json(const PipelineConfig& config);

// Every key: dotted name, default of the given preset as text, allowed values, meaning.
struct KeyInfo {
  std::string name, value, allowed, doc;
};
std::vector<KeyInfo> key_reference(const PipelineConfig& config);
// The same for tools (`tigris register --list-config --json`), in the accelerator's format
// (testbench/config.hpp, config_reference_json): {"keys": [{key, type (integer, number, bool,
// enum), unit, default (the given configuration's value), doc, and min / above (exclusive) / max
// or an enum's values}]}.
nlohmann::json key_reference_json(const PipelineConfig& config);

}  // namespace tigris::registration
