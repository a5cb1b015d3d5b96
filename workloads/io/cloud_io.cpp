// Point-cloud files (see cloud_io.hpp): dispatch by extension, whole-file reads and writes.
#include "cloud_io.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <limits>

#include "core/input_file.hpp"
#include "kitti_bin.hpp"
#include "pcd_reader.hpp"
#include "ply_reader.hpp"
#include "reader_util.hpp"

namespace tigris {
namespace {

namespace fs = std::filesystem;
using io_detail::fail;
using io_detail::printable;

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace

PointCloud parse_cloud(const std::string& path, const char* data, std::size_t size) {
  const std::string ext = lower_extension(path);
  PointCloud cloud;
  if (ext == ".bin") {
    cloud = parse_kitti_bin(reinterpret_cast<const unsigned char*>(data), size, path);
  } else if (ext == ".pcd") {
    cloud = parse_pcd(data, size, path);
  } else if (ext == ".ply") {
    cloud = parse_ply(data, size, path);
  } else {
    fail(path, "unknown point-cloud format '" + printable(ext) +
                   "' (expected .bin (KITTI), .pcd or .ply; the extension selects the format)");
  }
  validate_cloud(cloud, path);
  return cloud;
}

PointCloud load_cloud(const std::string& path) {
  check_input(path, "");
  const std::string ext = lower_extension(path);
  if (ext != ".bin" && ext != ".pcd" && ext != ".ply")
    fail(path, "unknown point-cloud format '" + printable(ext) +
                   "' (expected .bin (KITTI), .pcd or .ply; the extension selects the format)");
  const std::string bytes = read_input(path, "");
  return parse_cloud(path, bytes.data(), bytes.size());
}

void save_cloud(const std::string& path, const PointCloud& cloud) {
  const std::string ext = lower_extension(path);
  std::string bytes;
  if (ext == ".bin") {
    bytes = kitti_bin_bytes(cloud);
  } else if (ext == ".pcd" || ext == ".ply") {
    if (cloud.empty()) fail(path, "cannot write an empty cloud as " + ext + " (no reader accepts it)");
    bytes = ext == ".pcd" ? pcd_bytes(cloud) : ply_bytes(cloud);
  } else {
    fail(path, "unknown point-cloud format '" + printable(ext) + "' (expected .bin, .pcd or .ply)");
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) fail(path, "cannot open the file for writing");
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) fail(path, "write error");
}

}  // namespace tigris
