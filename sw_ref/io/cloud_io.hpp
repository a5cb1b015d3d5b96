// Point-cloud files: KITTI .bin (float32 x y z reflectance, little-endian, 16 bytes a point),
// .pcd and .ply (through PCL). The format is chosen by the file extension.
#pragma once

#include <string>

#include "../cloud.hpp"

namespace tigris {

// Loads and validates (validate_cloud) a cloud; throws InputError naming the file on a missing
// or unreadable file, a .bin whose size is not a multiple of 16, NaN/Inf points or no points.
PointCloud load_cloud(const std::string& path);

// Writes a cloud; the format follows the extension (.bin writes reflectance 0).
void save_cloud(const std::string& path, const PointCloud& cloud);

}  // namespace tigris
