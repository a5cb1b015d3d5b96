// Fuzz target: the PCD reader (workloads/io/pcd_reader.hpp).
// Input whose first byte is 0: the rest drives generate_pcd (cloud_gen.hpp); the generated
// valid file must read back exactly the points the generator put in. Any other input is a PCD
// file: the reader must give a clean error naming the file, or a cloud of as many points as
// the header announces (counted by an independent scan) that survives a write and re-read.
#include <sstream>
#include <string>
#include <vector>

#include "cloud_checks.hpp"
#include "workloads/io/pcd_reader.hpp"

namespace {

using namespace tigris_fuzz;
const char* const kTarget = "pcd";
const std::string kLabel = "fuzz.pcd";

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

}  // namespace

extern "C" int TIGRIS_FUZZ_ENTRY(const std::uint8_t* data, std::size_t size) {
  if (size > 0 && data[0] == 0) {
    ByteSource src(data + 1, size - 1);
    check_generated(generate_pcd(src), kTarget, kLabel, &tigris::parse_pcd);
  } else {
    check_file(data, size, kTarget, kLabel, &tigris::parse_pcd, &tigris::pcd_bytes, &announced_vertices);
  }
  return 0;
}

#ifdef TIGRIS_LIBFUZZER
#include "mutators.hpp"

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  static const std::vector<std::string> kWords = {
      "VERSION", "FIELDS",    "COLUMNS", "SIZE",       "TYPE",  "COUNT",  "WIDTH",
      "HEIGHT",  "VIEWPOINT", "POINTS",  "DATA",       "ascii", "binary", "binary_compressed",
      "0.7",     ".7",        "0.6",     "F",          "I",     "U",      "1",
      "2",       "4",         "8",       "0",          "3",     "x",      "y",
      "z",       "_",         "rgb",     "4294967295", "-1",    "nan",    "inf",
      "1e39",    "1e309",     "#"};
  static const std::vector<std::string> kLines = {"FIELDS x y z", "FIELDS x y z _ rgb", "SIZE 4 4 4",
                                                  "SIZE 8 8 8",   "SIZE 1 2 4",         "TYPE F F F",
                                                  "TYPE I U F",   "COUNT 1 1 1",        "COUNT 1 1 3",
                                                  "WIDTH 1",      "HEIGHT 1",           "HEIGHT 2",
                                                  "POINTS 1",     "POINTS 2",           "VIEWPOINT 0 0 0 1 0 0 0",
                                                  "DATA ascii",   "DATA binary",        "DATA binary_compressed",
                                                  "VERSION 0.7",  "# comment"};
  return structured_mutate(data, size, max_size, seed, generate_pcd, "DATA", kWords, kLines);
}
#endif
