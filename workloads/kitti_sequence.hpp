// A KITTI odometry sequence folder (docs/registration.md), as KITTI distributes it and
// `tigris synth` writes it: velodyne/NNNNNN.bin scans numbered from 000000 without a gap (or
// the scans in the folder itself when it has no velodyne/),
// poses.txt (optional: one 3x4 cam0 pose a line, frame i in frame 0's camera) and calib.txt
// (optional: its `Tr:` line, Velodyne -> cam0; without the file, the documented axis swap
// x_cam = -y_velo, y_cam = -z_velo, z_cam = x_velo of kitti_velo_to_cam()).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "pose.hpp"

namespace tigris {

struct KittiSequence {
  std::string dir;
  std::vector<std::string> scans;  // the .bin paths, frame 0 first
  // Ground truth in the Velodyne frame: frame i's Velodyne in frame 0's (inv(Tr) P_i Tr);
  // every pose of poses.txt (one a scan at least; more when the folder holds only the first
  // scans of a sequence); empty without poses.txt.
  std::vector<Pose> poses;
  Pose velo_to_cam = Pose::Identity();  // Tr
  std::string calibration;              // where Tr came from, for the run's report
  std::string note;                     // e.g. poses.txt has more poses than there are scans
};

// Reads the folder's listing, poses.txt and calib.txt (not the scans). Throws InputError
// naming the file: no such folder or no scan in it, a gap in the numbering (the missing
// file named), a poses.txt with fewer poses than scans (more: the first are used, `note` says
// so), a calib.txt without a well-formed Tr line.
KittiSequence read_kitti_sequence(const std::string& dir);

// calib.txt's `Tr:` line (12 numbers, 3x4 row-major). Throws InputError naming the file and
// line.
Pose read_kitti_calib_tr(const std::string& path);

// Velodyne-frame poses (frame i in frame 0) as KITTI poses.txt lines: cam0 poses Tr P inv(Tr),
// 12 numbers a line, enough digits to read back to 1e-12.
void write_kitti_poses(std::ostream& out, const std::vector<Pose>& velo_poses, const Pose& velo_to_cam);

}  // namespace tigris
