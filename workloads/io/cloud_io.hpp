// Point-cloud files: KITTI .bin (float32 x y z reflectance, little-endian, 16 bytes a point),
// .pcd and .ply, each read by the project's own parser (kitti_bin.hpp, pcd_reader.hpp,
// ply_reader.hpp say exactly what each accepts). The format is chosen by the file extension.
// No PCL here: PCL 1.13 misreads or aborts on valid files, and the parsers are small.
#pragma once

#include <string>

#include "sw_ref/cloud.hpp"

namespace tigris {

// Loads and validates (validate_cloud) a cloud; throws InputError naming the file (and the line,
// element or byte offset) on a missing or unreadable file, a malformed or truncated file,
// NaN/Inf or out-of-range points, or no points.
PointCloud load_cloud(const std::string& path);

// Parses file bytes as the format of `path`'s extension and validates the cloud, like
// load_cloud without the file system (the fuzz targets and tests use it).
PointCloud parse_cloud(const std::string& path, const char* data, std::size_t size);

// Writes a cloud; the format follows the extension: .bin (reflectance 0), .pcd (binary, v0.7,
// float32 x y z), .ply (binary_little_endian, float x y z). Throws InputError on failure.
void save_cloud(const std::string& path, const PointCloud& cloud);

}  // namespace tigris
