// Fuzz target: the PCD reader (sw_ref/io/pcd_reader.hpp).
// Input whose first byte is 0: the rest drives generate_pcd (cloud_gen.hpp); the generated
// valid file must read back exactly the points the generator put in. Any other input is a PCD
// file: the reader must give a clean error naming the file, or a cloud of as many points as
// the header announces (counted by an independent scan) that survives a write and re-read.
#include <sstream>
#include <string>
#include <vector>

#include "cloud_gen.hpp"
#include "fuzz_common.hpp"
#include "sw_ref/io/pcd_reader.hpp"

namespace {

using namespace tigris_fuzz;
const char* const kTarget = "pcd";
const std::string kLabel = "fuzz.pcd";

std::uint32_t bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

// "" when equal bit for bit, else the first difference.
std::string difference(const tigris::PointCloud& got, const tigris::PointCloud& want) {
  if (got.size() != want.size())
    return std::to_string(got.size()) + " points read, " + std::to_string(want.size()) + " expected";
  for (std::size_t i = 0; i < got.size(); ++i)
    if (bits(got[i].x) != bits(want[i].x) || bits(got[i].y) != bits(want[i].y) ||
        bits(got[i].z) != bits(want[i].z)) {
      std::ostringstream m;
      m.precision(9);
      m << "point " << i << " read as (" << got[i].x << ", " << got[i].y << ", " << got[i].z
        << "), expected (" << want[i].x << ", " << want[i].y << ", " << want[i].z << ")";
      return m.str();
    }
  return "";
}

// The point count of the header (POINTS, else WIDTH x HEIGHT), by a scan that shares nothing
// with the reader; -1 if none.
long long announced_vertices(const std::string& file) {
  std::istringstream in(file);
  std::string line;
  long long width = -1, height = 1, points = -1;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key, value;
    words >> key >> value;
    if (key == "DATA") break;
    if (key == "POINTS") points = std::stoll(value);
    if (key == "WIDTH") width = std::stoll(value);
    if (key == "HEIGHT") height = std::stoll(value);
  }
  return points >= 0 ? points : width >= 0 ? width * height : -1;
}

void check_raw(const std::uint8_t* data, std::size_t size) {
  tigris::PointCloud cloud;
  try {
    cloud = tigris::parse_pcd(reinterpret_cast<const char*>(data), size, kLabel);
  } catch (const tigris::InputError& e) {
    if (!names_source(e.what(), kLabel)) wrong_read(kTarget, std::string("error without the file name: ") + e.what());
    return;
  }
  const std::string file(reinterpret_cast<const char*>(data), size);
  const long long n = announced_vertices(file);
  if (n < 0 || static_cast<unsigned long long>(n) != cloud.size())
    wrong_read(kTarget, std::to_string(cloud.size()) + " points read, the header announces " + std::to_string(n));
  const std::string again = tigris::pcd_bytes(cloud);
  const std::string diff = difference(tigris::parse_pcd(again.data(), again.size(), kLabel), cloud);
  if (!diff.empty()) wrong_read(kTarget, "write and re-read: " + diff);
  try {
    tigris::validate_cloud(cloud, kLabel);
  } catch (const tigris::InputError& e) {
    if (!names_source(e.what(), kLabel)) wrong_read(kTarget, std::string("error without the file name: ") + e.what());
  }
}

void check_generated(const std::uint8_t* data, std::size_t size) {
  ByteSource src(data + 1, size - 1);
  const Generated g = generate_pcd(src);
  tigris::PointCloud cloud;
  try {
    cloud = tigris::parse_pcd(g.bytes.data(), g.bytes.size(), kLabel);
  } catch (const tigris::InputError& e) {
    wrong_read(kTarget, "a valid file (" + g.variant + ") rejected: " + e.what() + "\n" + g.bytes.substr(0, 600));
  }
  const std::string diff = difference(cloud, g.points);
  if (!diff.empty()) wrong_read(kTarget, g.variant + ": " + diff + "\n" + g.bytes.substr(0, 600));
}

}  // namespace

extern "C" int TIGRIS_FUZZ_ENTRY(const std::uint8_t* data, std::size_t size) {
  if (size > 0 && data[0] == 0)
    check_generated(data, size);
  else
    check_raw(data, size);
  return 0;
}

#ifdef TIGRIS_LIBFUZZER
#include "mutators.hpp"

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size,
                                               std::size_t max_size, unsigned int seed) {
  static const std::vector<std::string> kWords = {
      "VERSION", "FIELDS", "COLUMNS", "SIZE", "TYPE", "COUNT", "WIDTH", "HEIGHT", "VIEWPOINT",
      "POINTS", "DATA", "ascii", "binary", "binary_compressed", "0.7", ".7", "0.6", "F", "I", "U",
      "1", "2", "4", "8", "0", "3", "x", "y", "z", "_", "rgb", "4294967295", "-1", "nan", "inf",
      "1e39", "1e309", "#"};
  static const std::vector<std::string> kLines = {
      "FIELDS x y z", "FIELDS x y z _ rgb", "SIZE 4 4 4", "SIZE 8 8 8", "SIZE 1 2 4", "TYPE F F F",
      "TYPE I U F", "COUNT 1 1 1", "COUNT 1 1 3", "WIDTH 1", "HEIGHT 1", "HEIGHT 2", "POINTS 1",
      "POINTS 2", "VIEWPOINT 0 0 0 1 0 0 0", "DATA ascii", "DATA binary", "DATA binary_compressed",
      "VERSION 0.7", "# comment"};
  return structured_mutate(data, size, max_size, seed, generate_pcd, "DATA", kWords, kLines);
}
#endif
