#include "kitti_bin.hpp"

#include <cstdint>
#include <cstring>
#include <limits>

#include "reader_util.hpp"

namespace tigris {
namespace {

// Assembled byte by byte: independent of the host's byte order.
float float_from_le(const unsigned char* b) {
  const std::uint32_t u = static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8) |
                          (static_cast<std::uint32_t>(b[2]) << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

void float_to_le(float f, char* b) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  for (int i = 0; i < 4; ++i) b[i] = static_cast<char>((u >> (8 * i)) & 0xFFu);
}

}  // namespace

PointCloud parse_kitti_bin(const unsigned char* data, std::size_t size, const std::string& label) {
  if (size % 16 != 0)
    io_detail::fail(label, "file size " + std::to_string(size) +
                               " bytes is not a multiple of 16 (a KITTI .bin holds float32 x, y, "
                               "z, reflectance per point); the file is truncated or not a KITTI "
                               "scan");
  if (size / 16 > std::numeric_limits<std::uint32_t>::max() - 1)
    io_detail::fail(label, "too many points (at most 2^32 - 2)");
  PointCloud cloud(size / 16);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const unsigned char* p = data + 16 * i;
    cloud[i] = Point3{float_from_le(p), float_from_le(p + 4), float_from_le(p + 8)};
  }
  return cloud;
}

std::string kitti_bin_bytes(const PointCloud& cloud) {
  std::string bytes(16 * cloud.size(), '\0');
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    float_to_le(cloud[i].x, &bytes[16 * i]);
    float_to_le(cloud[i].y, &bytes[16 * i + 4]);
    float_to_le(cloud[i].z, &bytes[16 * i + 8]);
  }
  return bytes;
}

}  // namespace tigris
