// Point-cloud files (see cloud_io.hpp): dispatch by extension, whole-file reads and writes.
#include "cloud_io.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <limits>

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

std::string read_file(const std::string& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) fail(path, "cannot determine the file size (" + ec.message() + ")");
  if (size > static_cast<std::uintmax_t>(std::numeric_limits<std::streamsize>::max()) ||
      size > std::numeric_limits<std::size_t>::max() / 2)
    fail(path, "file too large");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file for reading");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  if (size > 0 && !in.read(&bytes[0], static_cast<std::streamsize>(size)))
    fail(path, "read error (the file changed while it was read?)");
  if (in.peek() != std::char_traits<char>::eof())
    fail(path, "read error (the file grew while it was read)");
  return bytes;
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
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) fail(path, "no such file");
  if (!fs::is_regular_file(st)) fail(path, "not a regular file");
  const std::string ext = lower_extension(path);
  if (ext != ".bin" && ext != ".pcd" && ext != ".ply")
    fail(path, "unknown point-cloud format '" + printable(ext) +
                   "' (expected .bin (KITTI), .pcd or .ply; the extension selects the format)");
  const std::string bytes = read_file(path);
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
