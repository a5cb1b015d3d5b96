// Fuzz target: the KITTI .bin reader (workloads/io/kitti_bin.hpp). A size that is not a multiple
// of 16 must give a clean error naming the file; any other input must read as size / 16 points
// whose x, y, z are the first three little-endian float32 of each 16-byte record, bit for bit
// (checked against memcpy on this little-endian host), and survive a write and re-read.
#include <string>

#include "fuzz_common.hpp"
#include "workloads/io/kitti_bin.hpp"

namespace {

using namespace tigris_fuzz;
const char* const kTarget = "kitti_bin";
const std::string kLabel = "fuzz.bin";

}  // namespace

extern "C" int TIGRIS_FUZZ_ENTRY(const std::uint8_t* data, std::size_t size) {
  static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the check decodes with memcpy");
  tigris::PointCloud cloud;
  try {
    cloud = tigris::parse_kitti_bin(data, size, kLabel);
  } catch (const tigris::InputError& e) {
    if (size % 16 == 0) wrong_read(kTarget, std::string("a multiple of 16 bytes rejected: ") + e.what());
    if (!names_source(e.what(), kLabel)) wrong_read(kTarget, std::string("error without the file name: ") + e.what());
    return 0;
  }
  if (size % 16 != 0) wrong_read(kTarget, std::to_string(size) + " bytes accepted");
  if (cloud.size() != size / 16)
    wrong_read(kTarget, std::to_string(cloud.size()) + " points read from " + std::to_string(size) + " bytes");
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    float f[3];
    std::memcpy(f, data + 16 * i, 12);
    if (float_bits(cloud[i].x) != float_bits(f[0]) || float_bits(cloud[i].y) != float_bits(f[1]) ||
        float_bits(cloud[i].z) != float_bits(f[2]))
      wrong_read(kTarget, "point " + std::to_string(i) + " differs from its bytes");
  }
  const std::string again = tigris::kitti_bin_bytes(cloud);
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (std::memcmp(again.data() + 16 * i, data + 16 * i, 12) != 0)
      wrong_read(kTarget, "point " + std::to_string(i) + " written back differently");
  try {
    tigris::validate_cloud(cloud, kLabel);
  } catch (const tigris::InputError& e) {
    if (!names_source(e.what(), kLabel)) wrong_read(kTarget, std::string("error without the file name: ") + e.what());
  }
  return 0;
}
