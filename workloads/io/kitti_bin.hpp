// KITTI Velodyne scans (.bin): float32 x, y, z, reflectance per point, little-endian, 16 bytes a
// point, no header. Reflectance is read past, not kept.
#pragma once

#include <cstddef>
#include <string>

#include "sw_ref/cloud.hpp"

namespace tigris {

// Decodes a whole .bin file held in memory. Throws InputError starting with `label` when the
// size is not a multiple of 16 or the file holds more than 2^32 - 1 points. Does not validate
// the points (load_cloud does: NaN/Inf, |x| > kMaxCoordinate, empty).
PointCloud parse_kitti_bin(const unsigned char* data, std::size_t size, const std::string& label);

// The bytes of a .bin file of `cloud` (reflectance 0).
std::string kitti_bin_bytes(const PointCloud& cloud);

}  // namespace tigris
