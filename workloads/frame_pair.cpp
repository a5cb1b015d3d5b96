#include "frame_pair.hpp"

#include <algorithm>

#include "core/flag_values.hpp"
#include "io/cloud_io.hpp"
#include "synthetic.hpp"

namespace tigris {

FramePair load_frame_pair(const FramePairSpec& o) {
  FramePair f;
  if (o.source.empty()) {
    SyntheticConfig sc;
    sc.seed = o.seed;
    const SyntheticPair pair = make_synthetic_pair(sc);
    f.source = pair.frame1;
    f.target = pair.frame0;
    const std::string tag = " (seed " + std::to_string(o.seed) + ")";
    f.source_name = "synthetic:frame1" + tag;
    f.target_name = "synthetic:frame0" + tag;
    Pose t;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) t(r, c) = pair.frame1_to_frame0[static_cast<std::size_t>(4 * r + c)];
    f.truth = t;
    f.truth_name = "synthetic pair's known pose";
  } else {
    f.source = load_cloud(o.source);
    f.target = load_cloud(o.target);
    f.source_name = o.source;
    f.target_name = o.target;
  }
  if (!o.ground_truth.empty()) {
    f.truth = read_pose_file(o.ground_truth);
    f.truth_name = o.ground_truth;
  } else if (!o.kitti_poses.empty()) {
    const auto [s, t] = parse_frame_pair(o.kitti_frames);
    f.truth = kitti_relative_velo_pose(o.kitti_poses, s, t);
    f.truth_name = o.kitti_poses + " frames " + o.kitti_frames + " (camera -> Velodyne axes)";
    // Both frames within a run of equal ground-truth steps from frame 0 (KITTI 00's first ~15).
    const std::size_t steps = equal_steps(read_kitti_poses(o.kitti_poses));
    if (steps >= kEqualStepsWarn && static_cast<std::size_t>(std::max(s, t)) <= steps)
      f.truth_warning = equal_steps_warning(steps);
  }
  return f;
}

}  // namespace tigris
