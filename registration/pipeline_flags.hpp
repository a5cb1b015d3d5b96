// The pipeline's configuration from `tigris register`'s flags (odometry forwards the same
// flags): the preset, then --config, each --set, and the flags over them, each flag setting its
// key through the key table (so it has the key's range and registration.json reads back).
#pragma once

#include <string>
#include <vector>

#include "pipeline_config.hpp"

namespace tigris::registration {

// Each empty: the key keeps the preset's (or the file's) value.
struct PipelineFlags {
  std::string preset = "dp4";
  std::string config;             // a JSON file over the preset
  std::vector<std::string> sets;  // key=value
  std::string search;             // flann, exact, approx, accel (exact on the model), accel-approx
  std::string height;             // 0..30 or "full": search.top_height
  std::string approx_thd;         // metres: search.nn_thd, and radius_thd 0.4 * T / 1.2; implies approx
  std::string inject_kth;         // inject.rpce_kth
  std::string inject_shell;       // "R1,R2": inject.normals_shell_inner/_outer
};

// The configuration, validated; std::invalid_argument naming the flag or key that does not hold.
PipelineConfig config_from_flags(const PipelineFlags& f);

}  // namespace tigris::registration
