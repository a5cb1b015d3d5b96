// Fuzz target: the PLY reader (workloads/io/ply_reader.hpp).
// Input whose first byte is 0: the rest drives generate_ply (cloud_gen.hpp); the generated
// valid file must read back exactly the points the generator put in. Any other input is a PLY
// file: the reader must give a clean error naming the file, or a cloud of as many points as
// the header announces (counted by an independent scan) that survives a write and re-read.
#include <sstream>
#include <string>
#include <vector>

#include "cloud_checks.hpp"
#include "workloads/io/ply_reader.hpp"

namespace {

using namespace tigris_fuzz;
const char* const kTarget = "ply";
const std::string kLabel = "fuzz.ply";

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

}  // namespace

extern "C" int TIGRIS_FUZZ_ENTRY(const std::uint8_t* data, std::size_t size) {
  if (size > 0 && data[0] == 0) {
    ByteSource src(data + 1, size - 1);
    check_generated(generate_ply(src), kTarget, kLabel, &tigris::parse_ply);
  } else {
    check_file(data, size, kTarget, kLabel, &tigris::parse_ply, &tigris::ply_bytes, &announced_vertices);
  }
  return 0;
}

#ifdef TIGRIS_LIBFUZZER
#include "mutators.hpp"

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  static const std::vector<std::string> kWords = {"ply",
                                                  "format",
                                                  "ascii",
                                                  "binary_little_endian",
                                                  "binary_big_endian",
                                                  "1.0",
                                                  "element",
                                                  "vertex",
                                                  "face",
                                                  "property",
                                                  "list",
                                                  "char",
                                                  "uchar",
                                                  "short",
                                                  "ushort",
                                                  "int",
                                                  "uint",
                                                  "float",
                                                  "double",
                                                  "int8",
                                                  "uint8",
                                                  "int16",
                                                  "uint16",
                                                  "int32",
                                                  "uint32",
                                                  "float32",
                                                  "float64",
                                                  "x",
                                                  "y",
                                                  "z",
                                                  "end_header",
                                                  "comment",
                                                  "obj_info",
                                                  "0",
                                                  "1",
                                                  "4294967295",
                                                  "-1",
                                                  "nan",
                                                  "inf",
                                                  "1e39",
                                                  "1e309"};
  static const std::vector<std::string> kLines = {"property list uint float e",
                                                  "property list int double e",
                                                  "property list uchar int vertex_indices",
                                                  "property list char uchar l",
                                                  "property double x",
                                                  "property int y",
                                                  "property uchar z",
                                                  "element face 1",
                                                  "element vertex 1",
                                                  "element empty 5",
                                                  "comment hello",
                                                  "obj_info x",
                                                  "format binary_big_endian 1.0",
                                                  "format ascii 1.0",
                                                  "property float w"};
  return structured_mutate(data, size, max_size, seed, generate_ply, "end_header", kWords, kLines);
}
#endif
