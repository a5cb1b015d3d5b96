// Fuzz target: the PLY reader (sw_ref/io/ply_reader.hpp).
// Input whose first byte is 0: the rest drives generate_ply (cloud_gen.hpp); the generated
// valid file must read back exactly the points the generator put in. Any other input is a PLY
// file: the reader must give a clean error naming the file, or a cloud of as many points as
// the header announces (counted by an independent scan) that survives a write and re-read.
#include <sstream>
#include <string>
#include <vector>

#include "cloud_gen.hpp"
#include "fuzz_common.hpp"
#include "sw_ref/io/ply_reader.hpp"

namespace {

using namespace tigris_fuzz;
const char* const kTarget = "ply";
const std::string kLabel = "fuzz.ply";

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

// The vertex count of the header, by a scan that shares nothing with the reader; -1 if none.
long long announced_vertices(const std::string& file) {
  std::istringstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string a, b, c;
    words >> a >> b >> c;
    if (a == "end_header") break;
    if (a == "element" && b == "vertex") return std::stoll(c);
  }
  return -1;
}

void check_raw(const std::uint8_t* data, std::size_t size) {
  tigris::PointCloud cloud;
  try {
    cloud = tigris::parse_ply(reinterpret_cast<const char*>(data), size, kLabel);
  } catch (const tigris::InputError& e) {
    if (!names_source(e.what(), kLabel)) wrong_read(kTarget, std::string("error without the file name: ") + e.what());
    return;
  }
  const std::string file(reinterpret_cast<const char*>(data), size);
  const long long n = announced_vertices(file);
  if (n < 0 || static_cast<unsigned long long>(n) != cloud.size())
    wrong_read(kTarget, std::to_string(cloud.size()) + " points read, the header announces " + std::to_string(n));
  const std::string again = tigris::ply_bytes(cloud);
  const std::string diff = difference(tigris::parse_ply(again.data(), again.size(), kLabel), cloud);
  if (!diff.empty()) wrong_read(kTarget, "write and re-read: " + diff);
  try {
    tigris::validate_cloud(cloud, kLabel);
  } catch (const tigris::InputError& e) {
    if (!names_source(e.what(), kLabel)) wrong_read(kTarget, std::string("error without the file name: ") + e.what());
  }
}

void check_generated(const std::uint8_t* data, std::size_t size) {
  ByteSource src(data + 1, size - 1);
  const Generated g = generate_ply(src);
  tigris::PointCloud cloud;
  try {
    cloud = tigris::parse_ply(g.bytes.data(), g.bytes.size(), kLabel);
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
      "ply", "format", "ascii", "binary_little_endian", "binary_big_endian", "1.0", "element",
      "vertex", "face", "property", "list", "char", "uchar", "short", "ushort", "int", "uint",
      "float", "double", "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32",
      "float64", "x", "y", "z", "end_header", "comment", "obj_info", "0", "1", "4294967295",
      "-1", "nan", "inf", "1e39", "1e309"};
  static const std::vector<std::string> kLines = {
      "property list uint float e", "property list int double e", "property list uchar int vertex_indices",
      "property list char uchar l", "property double x", "property int y", "property uchar z",
      "element face 1", "element vertex 1", "element empty 5", "comment hello", "obj_info x",
      "format binary_big_endian 1.0", "format ascii 1.0", "property float w"};
  return structured_mutate(data, size, max_size, seed, generate_ply, "end_header", kWords, kLines);
}
#endif
