// The two frames `tigris register` registers, and the ground truth when there is one: two
// point-cloud files (cloud_io.hpp) or the built-in synthetic pair with its known pose; the
// truth from a pose file, or from a KITTI poses.txt and two of its frames (camera -> Velodyne
// axes), with a warning when both frames lie in a run of equal ground-truth steps.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "pose.hpp"
#include "sw_ref/cloud.hpp"

namespace tigris {

struct FramePairSpec {
  std::string source, target;  // empty: the built-in synthetic pair of `seed`
  std::uint64_t seed = 1;
  std::string ground_truth;                       // a 4x4 or 3x4 pose file
  std::string kitti_poses, kitti_frames = "1,0";  // or: a poses.txt and SOURCE,TARGET lines of it
};

struct FramePair {
  PointCloud source, target;
  std::string source_name, target_name;
  std::optional<Pose> truth;  // target <- source
  std::string truth_name, truth_warning;
};

// Errors name the file (or the frames) at fault.
FramePair load_frame_pair(const FramePairSpec& spec);

}  // namespace tigris
