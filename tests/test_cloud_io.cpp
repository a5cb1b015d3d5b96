// Point-cloud files (workloads/io/cloud_io.hpp): round trips, every kind of bad input, KITTI frames.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "test_util.hpp"
#include "traces/results_csv.hpp"
#include "workloads/io/cloud_io.hpp"
#include "workloads/io/lzf.hpp"
#include "workloads/synthetic.hpp"

using tigris::test::bits;
using tigris::test::same_bits;

namespace {

namespace fs = std::filesystem;
using tigris::InputError;
using tigris::Point3;
using tigris::PointCloud;

// A fresh directory under the system temp folder, removed with everything in it at scope exit.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    const auto now = std::chrono::steady_clock::now().time_since_epoch().count();
    for (int attempt = 0; attempt < 100; ++attempt) {
      const std::string name =
          "tigris_test_io_" + std::to_string(rd()) + "_" + std::to_string(now) + "_" + std::to_string(attempt);
      path_ = fs::temp_directory_path() / name;
      if (fs::create_directory(path_)) return;
    }
    throw std::runtime_error("cannot create a temporary directory");
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  REQUIRE(out.good());
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// KITTI .bin bytes of the given points (x, y, z, reflectance 0), little-endian.
std::string kitti_bytes(const std::vector<std::array<float, 3>>& points) {
  std::string bytes;
  for (const auto& p : points)
    for (float f : {p[0], p[1], p[2], 0.0f}) {
      std::uint32_t u;
      std::memcpy(&u, &f, 4);
      for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<char>((u >> (8 * i)) & 0xFFu));
    }
  return bytes;
}

// load_cloud(path) must throw InputError whose message names the file (and holds `detail`).
void require_input_error(const std::string& path, const std::string& detail = "") {
  INFO("file " << path);
  try {
    tigris::load_cloud(path);
    FAIL("no InputError for " << path);
  } catch (const InputError& e) {
    const std::string msg = e.what();
    INFO("message: " << msg);
    CHECK(msg.find(fs::path(path).filename().string()) != std::string::npos);
    if (!detail.empty()) CHECK(msg.find(detail) != std::string::npos);
  }
}

// A cloud with awkward values: exact float round trips must keep every bit.
PointCloud awkward_cloud() {
  const tigris::SyntheticPair pair = tigris::make_synthetic_pair();
  PointCloud cloud(pair.frame0.begin(), pair.frame0.begin() + 5000);
  cloud.push_back(Point3{-0.0f, 0.0f, 1e-40f});  // negative zero and a subnormal
  // The largest magnitude accepted (FLT_MAX is refused: its distances overflow) and the
  // smallest normal number.
  cloud.push_back(Point3{tigris::kMaxCoordinate, -std::numeric_limits<float>::min(), 0.1f});
  cloud.push_back(Point3{1.0f / 3.0f, -123456.789f, 3.4e-38f});
  return cloud;
}

// Small valid .pcd / .ply files for the corruption tests.
std::string valid_file(const TempDir& dir, const std::string& name) {
  PointCloud cloud;
  for (int i = 0; i < 200; ++i) cloud.push_back(Point3{0.5f * i, 1.0f - 0.25f * i, 0.125f * (i % 7)});
  const std::string path = dir.file(name);
  tigris::save_cloud(path, cloud);
  return path;
}

}  // namespace

TEST_CASE("cloud_io: .bin, .pcd and .ply round trips keep every bit", "[io]") {
  TempDir dir;
  const PointCloud cloud = awkward_cloud();
  for (const char* name : {"cloud.bin", "cloud.pcd", "cloud.ply", "UPPER.PCD", "upper.Ply"}) {
    INFO(name);
    const std::string path = dir.file(name);
    tigris::save_cloud(path, cloud);
    const PointCloud back = tigris::load_cloud(path);
    CHECK(same_bits(cloud, back));
  }
  // .bin is exactly 16 little-endian bytes a point, reflectance 0.
  const std::string bytes = read_bytes(dir.file("cloud.bin"));
  REQUIRE(bytes.size() == 16 * cloud.size());
  std::vector<std::array<float, 3>> xyz;
  for (const Point3& p : cloud) xyz.push_back({p.x, p.y, p.z});
  CHECK(bytes == kitti_bytes(xyz));
}

TEST_CASE("cloud_io: missing file, unknown extension, bad .bin size", "[io]") {
  TempDir dir;
  require_input_error(dir.file("does_not_exist.bin"), "no such file");
  require_input_error(dir.file("does_not_exist.pcd"), "no such file");

  const std::string xyz = dir.file("points.xyz");
  write_bytes(xyz, "1 2 3\n");
  require_input_error(xyz, "unknown point-cloud format");
  const std::string no_ext = dir.file("points");
  write_bytes(no_ext, kitti_bytes({{1.0f, 2.0f, 3.0f}}));
  require_input_error(no_ext, "unknown point-cloud format");

  const std::string odd = dir.file("odd_size.bin");
  write_bytes(odd, kitti_bytes({{1.0f, 2.0f, 3.0f}}) + "x");
  require_input_error(odd, "17 bytes");

  fs::create_directory(dir.file("folder.pcd"));
  require_input_error(dir.file("folder.pcd"), "not a regular file");

  CHECK_THROWS_AS(tigris::save_cloud(dir.file("out.xyz"), awkward_cloud()), InputError);
  CHECK_THROWS_AS(tigris::save_cloud(dir.file("no_such_dir/out.bin"), awkward_cloud()), InputError);
  CHECK_THROWS_AS(tigris::save_cloud(dir.file("no_such_dir/out.pcd"), awkward_cloud()), InputError);
}

TEST_CASE("cloud_io: NaN, Inf and empty clouds are rejected", "[io]") {
  TempDir dir;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();

  const std::string with_nan = dir.file("with_nan.bin");
  write_bytes(with_nan, kitti_bytes({{1.0f, 2.0f, 3.0f}, {4.0f, nan, 6.0f}}));
  require_input_error(with_nan, "point 1 has a non-finite coordinate");
  const std::string with_inf = dir.file("with_inf.bin");
  write_bytes(with_inf, kitti_bytes({{1.0f, 2.0f, -inf}}));
  require_input_error(with_inf, "point 0 has a non-finite coordinate");
  // A list property before x, y, z in the vertex element (PCL 1.13 read point 0 as
  // (7, 7, 1)): read past, x, y, z exact.
  const std::string list_ply = dir.file("list.ply");
  write_bytes(list_ply,
              "ply\nformat ascii 1.0\nelement vertex 4\nproperty list uint float e\nproperty float x\n"
              "property float y\nproperty float z\nend_header\n3 7 7 7 1 2 3\n1 7 10 20 30\n1 7 -5 -6 -7\n"
              "1 7 100 0 0\n");
  CHECK(same_bits(tigris::load_cloud(list_ply),
                  {Point3{1, 2, 3}, Point3{10, 20, 30}, Point3{-5, -6, -7}, Point3{100, 0, 0}}));
  // Lists in other elements (faces) are fine: the vertices read exactly.
  const std::string face_ply = dir.file("face.ply");
  write_bytes(face_ply,
              "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n1 2 3\n4 5 6\n3 0 1 1\n");
  const PointCloud faces = tigris::load_cloud(face_ply);
  REQUIRE(faces.size() == 2);
  CHECK(faces[0].x == 1.0f);
  CHECK(faces[1].z == 6.0f);
  // Finite but huge: squared differences would overflow float32 and every distance be inf.
  const std::string huge = dir.file("huge.bin");
  write_bytes(huge, kitti_bytes({{1.0f, 2.0f, 3.0f}, {2e19f, 0.0f, 0.0f}}));
  require_input_error(huge, "point 1 (2e+19, 0, 0) has a coordinate beyond +-1e18");
  const std::string edge = dir.file("edge.bin");
  write_bytes(edge, kitti_bytes({{1e18f, -1e18f, 1e18f}, {-1e18f, 1e18f, -1e18f}}));
  CHECK(tigris::load_cloud(edge).size() == 2);  // the limit itself is accepted
  const std::string empty = dir.file("empty.bin");
  write_bytes(empty, "");
  require_input_error(empty, "empty");

  // The same policy for .pcd and .ply: a NaN point.
  PointCloud cloud = {Point3{1.0f, 2.0f, 3.0f}, Point3{nan, 0.0f, 0.0f}};
  for (const char* name : {"with_nan.pcd", "with_nan.ply"}) {
    tigris::save_cloud(dir.file(name), cloud);
    require_input_error(dir.file(name), "point 1 has a non-finite coordinate");
  }
  // Headers that announce no point.
  const std::string pcd0 = dir.file("zero.pcd");
  write_bytes(pcd0,
              "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 0\n"
              "HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 0\nDATA ascii\n");
  require_input_error(pcd0, "empty");
  const std::string ply0 = dir.file("zero.ply");
  write_bytes(ply0,
              "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
              "property float y\nproperty float z\nend_header\n");
  require_input_error(ply0, "empty");
}

TEST_CASE("cloud_io: other .pcd and .ply layouts", "[io]") {
  TempDir dir;
  // ASCII PCD with an extra field, Windows line ends.
  const std::string ascii = dir.file("ascii.pcd");
  write_bytes(ascii,
              "# .PCD v0.7\r\nVERSION 0.7\r\nFIELDS x y z intensity\r\nSIZE 4 4 4 4\r\n"
              "TYPE F F F F\r\nCOUNT 1 1 1 1\r\nWIDTH 2\r\nHEIGHT 1\r\n"
              "VIEWPOINT 0 0 0 1 0 0 0\r\nPOINTS 2\r\nDATA ascii\r\n1.5 -2 3 9\r\n4 5 6.25 9\r\n");
  PointCloud c = tigris::load_cloud(ascii);
  REQUIRE(c.size() == 2);
  CHECK(c[0].x == 1.5f);
  CHECK(c[1].z == 6.25f);

  // float64 coordinates are rounded to float32; big-endian binary PLY.
  const std::string dbl = dir.file("double.ply");
  std::string body;
  for (double v : {1.5, 2.0, 0.1}) {
    char b[8];
    std::memcpy(b, &v, 8);  // host order: this test assumes a little-endian host
    body.append(b, 8);
  }
  write_bytes(dbl,
              "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty double x\n"
              "property double y\nproperty double z\nend_header\n" +
                  body);
  c = tigris::load_cloud(dbl);
  REQUIRE(c.size() == 1);
  CHECK(c[0].z == 0.1f);

  const std::string be = dir.file("big_endian.ply");
  write_bytes(be, std::string("ply\nformat binary_big_endian 1.0\nelement vertex 1\n"
                              "property float x\nproperty float y\nproperty float z\n"
                              "end_header\n") +
                      std::string("\x3f\xc0\x00\x00\x40\x00\x00\x00\xc0\x40\x00\x00", 12));
  c = tigris::load_cloud(be);
  REQUIRE(c.size() == 1);
  CHECK(c[0].x == 1.5f);
  CHECK(c[0].y == 2.0f);
  CHECK(c[0].z == -3.0f);

  // Missing or non-float coordinate fields.
  const std::string no_z = dir.file("no_z.ply");
  write_bytes(no_z,
              "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
              "property float y\nend_header\n1 2\n");
  require_input_error(no_z, "no 'z' property");
  // Integer coordinates are converted to float32 (any scalar type).
  const std::string int_xyz = dir.file("int_xyz.pcd");
  write_bytes(int_xyz, "FIELDS x y z\nSIZE 4 4 4\nTYPE I I I\nPOINTS 1\nDATA ascii\n1 2 -3\n");
  CHECK(same_bits(tigris::load_cloud(int_xyz), {Point3{1, 2, -3}}));
  // A word that is not a number (PCL itself would read it as 0).
  const std::string word = dir.file("word.pcd");
  write_bytes(word, "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 abc 3\n");
  require_input_error(word, "'abc' is not a valid float32");
  // Other spellings of NaN and Inf reach validate_cloud as such.
  for (const char* value : {"inf", "-inf", "-nan", "NaN", "1e999"}) {
    const std::string path = dir.file(std::string("value") + value + ".pcd");
    write_bytes(path, std::string("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 ") + value + " 3\n");
    require_input_error(path, "non-finite coordinate");
  }
  // NaN outside x, y, z (normals, say) is fine.
  const std::string normals = dir.file("normals.pcd");
  write_bytes(normals,
              "FIELDS x y z normal_x\nSIZE 4 4 4 4\nTYPE F F F F\nPOINTS 1\nDATA ascii\n"
              "1 2 3 nan\n");
  CHECK(tigris::load_cloud(normals).size() == 1);
}

TEST_CASE("cloud_io: truncated and corrupt .pcd and .ply files give InputError", "[io]") {
  TempDir dir;
  for (const char* name : {"valid.pcd", "valid.ply"}) {
    const std::string path = valid_file(dir, name);
    const std::string bytes = read_bytes(path);
    const std::string ext = fs::path(name).extension().string();
    INFO(name);
    REQUIRE(tigris::load_cloud(path).size() == 200);

    // Cut inside the header, right after it, and inside the data.
    const std::size_t header_end =
        bytes.find(ext == ".pcd" ? "DATA binary\n" : "end_header\n") + (ext == ".pcd" ? 12 : 11);
    for (std::size_t cut : {std::size_t{0}, std::size_t{3}, header_end / 2, header_end - 1, header_end, header_end + 7,
                            (header_end + bytes.size()) / 2, bytes.size() - 1}) {
      const std::string cut_path = dir.file("cut" + std::to_string(cut) + ext);
      write_bytes(cut_path, bytes.substr(0, cut));
      require_input_error(cut_path);
    }
    // Random bytes, and a valid header followed by random bytes of the wrong length.
    std::mt19937_64 rng(7);
    std::string noise;
    for (int i = 0; i < 4000; ++i) noise.push_back(static_cast<char>(rng() & 0xFF));
    const std::string noise_path = dir.file("noise" + ext);
    write_bytes(noise_path, noise);
    require_input_error(noise_path);
    const std::string short_body = dir.file("short_body" + ext);
    write_bytes(short_body, bytes.substr(0, header_end) + noise.substr(0, 100));
    require_input_error(short_body, "truncated");
  }
  // Headers that announce far more points than the file holds: rejected before anything is
  // allocated for them.
  const std::string huge_pcd = dir.file("huge.pcd");
  write_bytes(huge_pcd,
              "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2000000000\nHEIGHT 1\n"
              "POINTS 2000000000\nDATA binary\n" +
                  std::string(24, '\0'));
  require_input_error(huge_pcd, "truncated");
  const std::string huge_ply = dir.file("huge.ply");
  write_bytes(huge_ply,
              "ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\n"
              "property float x\nproperty float y\nproperty float z\nend_header\n" +
                  std::string(24, '\0'));
  require_input_error(huge_ply, "truncated");
  // A header keyword PCD does not have (PCL 1.13 crashed on it).
  const std::string unknown = dir.file("unknown_key.pcd");
  write_bytes(unknown,
              "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nFOO 1\nPOINTS 1\n"
              "DATA ascii\n1 2 3\n");
  require_input_error(unknown, unknown + ":5: corrupt PCD header: unknown line 'FOO'");
  try {  // the file is named once, as every reader error names it
    tigris::load_cloud(unknown);
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).rfind(unknown + ":5: corrupt", 0) == 0);
  }
}

TEST_CASE("cloud_io: randomly damaged files never crash the reader", "[io]") {
  // A small fuzz: every damaged file either still loads or gives InputError, nothing else.
  TempDir dir;
  std::mt19937_64 rng(2024);
  int loaded = 0, rejected = 0;
  for (const char* name : {"valid.pcd", "valid.ply"}) {
    const std::string bytes = read_bytes(valid_file(dir, name));
    const std::string ext = fs::path(name).extension().string();
    for (int trial = 0; trial < 150; ++trial) {
      std::string damaged = bytes;
      if (trial % 3 == 0) {
        damaged.resize(rng() % bytes.size());
      } else {
        const std::size_t span = trial % 3 == 1 ? std::min<std::size_t>(bytes.size(), 250) : bytes.size();
        for (int k = 1 + static_cast<int>(rng() % 6); k > 0; --k)
          damaged[rng() % span] = static_cast<char>(rng() & 0xFF);
      }
      const std::string path = dir.file("damaged" + std::to_string(trial) + ext);
      write_bytes(path, damaged);
      try {
        tigris::load_cloud(path);
        ++loaded;
      } catch (const InputError& e) {
        ++rejected;
        REQUIRE(std::string(e.what()).find(path) != std::string::npos);
      } catch (const std::exception& e) {
        FAIL("not an InputError for " << path << ": " << e.what());
      }
    }
  }
  CHECK(rejected > 100);
  CHECK(loaded + rejected == 300);
}

TEST_CASE("cloud_io: the KITTI frames of ../shared/data load", "[io][kitti]") {
  const std::string dir = std::string(TIGRIS_DATA_DIR) + "/kitti-00";
  if (!fs::is_directory(dir)) {
    WARN("KITTI data not found at " << dir
                                    << ": skipping this test (configure with "
                                       "-DTIGRIS_DATA_DIR=<folder with kitti-00/> to run it)");
    return;
  }
  const PointCloud f0 = tigris::load_cloud(dir + "/000000.bin");
  const PointCloud f1 = tigris::load_cloud(dir + "/000001.bin");
  CHECK(f0.size() == 124668u);
  CHECK(f1.size() == 124605u);
  REQUIRE(!f0.empty());
  // The first point of frame 0, bit for bit (little-endian decoding).
  CHECK(f0[0].x == 52.89794158935547f);
  CHECK(f0[0].y == 0.02298973873257637f);
  CHECK(f0[0].z == 1.9979945421218872f);
}

// ---------------------------------------------------------------------------------------------
// The project's own PLY and PCD readers: layouts PCL misread or aborted on, and
// errors that name the file and the line, element or byte offset.

namespace {

// Little- or big-endian bytes of values, for hand-built binary files (a little-endian host).
struct Body {
  bool big = false;
  std::string bytes;
  template <class T>
  Body& put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    if (big) std::reverse(b, b + sizeof v);
    bytes.append(b, sizeof v);
    return *this;
  }
  Body& xyz(float x, float y, float z) { return put(x).put(y).put(z); }
};

PointCloud parse(const std::string& name, const std::string& bytes) {
  return tigris::parse_cloud(name, bytes.data(), bytes.size());
}

// parse(name, bytes) must throw InputError starting with the name and holding `detail`.
void require_parse_error(const std::string& name, const std::string& bytes, const std::string& detail) {
  INFO("file " << name << ", expecting '" << detail << "'");
  try {
    parse(name, bytes);
    FAIL("no InputError");
  } catch (const InputError& e) {
    const std::string msg = e.what();
    INFO("message: " << msg);
    CHECK(msg.rfind(name + ":", 0) == 0);
    CHECK(msg.find(detail) != std::string::npos);
  }
}

const PointCloud kIssuePoints = {Point3{1, 2, 3}, Point3{10, 20, 30}, Point3{-5, -6, -7}, Point3{100, 0, 0}};

std::string ply_header(const std::string& format, std::uint64_t n, const std::string& props) {
  return "ply\nformat " + format + " 1.0\nelement vertex " + std::to_string(n) + "\n" + props + "end_header\n";
}

// LZF data of literal runs only (valid input for any LZF decompressor).
std::string lzf_literals(const std::string& raw) {
  std::string out;
  for (std::size_t k = 0; k < raw.size(); k += 32) {
    const std::size_t len = std::min<std::size_t>(32, raw.size() - k);
    out.push_back(static_cast<char>(len - 1));
    out.append(raw, k, len);
  }
  return out;
}

std::string u32_le(std::uint32_t v) { return Body{}.put(v).bytes; }

}  // namespace

TEST_CASE("ply: list properties in the vertex element are read past", "[io]") {
  const std::string list_first = "property list uint float e\nproperty float x\nproperty float y\nproperty float z\n";
  for (bool big : {false, true}) {
    INFO("big-endian " << big);
    Body b{big, ""};
    b.put<std::uint32_t>(3).put(7.0f).put(7.0f).put(7.0f).xyz(1, 2, 3);
    b.put<std::uint32_t>(1).put(7.0f).xyz(10, 20, 30);
    b.put<std::uint32_t>(0).xyz(-5, -6, -7);  // an empty list
    b.put<std::uint32_t>(2).put(7.0f).put(7.0f).xyz(100, 0, 0);
    const std::string format = big ? "binary_big_endian" : "binary_little_endian";
    CHECK(same_bits(parse("uint_count.ply", ply_header(format, 4, list_first) + b.bytes), kIssuePoints));
  }
  // An int count (PCL 1.13 aborted on it), uchar/double lists between the coordinates, a char
  // count of uchar items after them.
  Body b;
  for (const Point3& p : kIssuePoints) {
    b.put<std::int32_t>(1).put(9.0f).put(p.x).put<std::uint8_t>(2).put(0.5).put(-1e300);
    b.put(p.y).put(p.z).put<std::int8_t>(3).put<std::uint8_t>(1).put<std::uint8_t>(2).put<std::uint8_t>(3);
  }
  const std::string mixed = ply_header("binary_little_endian", 4,
                                       "property list int float e\nproperty float x\n"
                                       "property list uchar double n\nproperty float y\nproperty float z\n"
                                       "property list char uchar c\n");
  CHECK(same_bits(parse("mixed_lists.ply", mixed + b.bytes), kIssuePoints));
  // The same in ASCII.
  const std::string ascii = ply_header("ascii", 4,
                                       "property list int float e\nproperty float x\n"
                                       "property list uchar double n\nproperty float y\nproperty float z\n") +
                            "1 9 1 2 0.5 -1e300 2 3\n0 10 0 20 30\n2 1 1 -5 1 nan -6 -7\n0 100 0 0 0\n";
  CHECK(same_bits(parse("mixed_lists_ascii.ply", ascii), kIssuePoints));
}

TEST_CASE("ply: element order, every scalar type, comments, CRLF", "[io]") {
  // Elements before and after the vertex element (their lists read past), one with no
  // properties and a large count, one with no entries; comments and obj_info anywhere.
  const std::string header =
      "ply\ncomment first\nformat binary_big_endian 1.0\nobj_info made by hand\n"
      "element face 2\nproperty list uchar int vertex_indices\nproperty uchar flags\n"
      "element nothing 1000000000\nelement vertex 2\ncomment between\nproperty int8 x\n"
      "property uint16 y\nproperty int z\nproperty double w\nelement edge 0\nproperty int a\n"
      "element tail 1\nproperty list ushort float t\nend_header\n";
  Body b{true, ""};
  b.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2).put<std::uint8_t>(7);
  b.put<std::uint8_t>(0).put<std::uint8_t>(7);
  b.put<std::int8_t>(-128).put<std::uint16_t>(65535).put<std::int32_t>(-2147483647 - 1).put(0.0);
  b.put<std::int8_t>(127).put<std::uint16_t>(0).put<std::int32_t>(16777217).put(0.0);
  b.put<std::uint16_t>(1).put(5.0f);
  CHECK(same_bits(parse("order.ply", header + b.bytes),
                  {Point3{-128, 65535, -2147483648.0f}, Point3{127, 0, 16777216.0f}}));
  // The other type names, in ASCII: uint rounds to the nearest float32, double too.
  const std::string types = ply_header("ascii", 2,
                                       "property uint x\nproperty double y\nproperty float32 z\n"
                                       "property uchar r\nproperty short s\nproperty ushort t\n"
                                       "property char u\nproperty float64 v\nproperty int16 w\n") +
                            "4294967295 0.1 +1.5 255 -32768 65535 -128 1e308 32767\n"
                            "0 -0.3 -2.5e-3 0 0 0 0 -inf 0\n";
  CHECK(same_bits(parse("types.ply", types), {Point3{4294967296.0f, 0.1f, 1.5f}, Point3{0, -0.3f, -2.5e-3f}}));
  // CRLF: the header of a binary file (its data starts after the LF of end_header; the first
  // data byte here is a CR) and every line of an ASCII file.
  Body crlf;
  crlf.put<std::uint32_t>(0x3F80000Du).xyz(2, 3, 4).put(5.0f).put(6.0f);  // x begins with byte 0x0D
  float x0;
  const std::uint32_t x0_bits = 0x3F80000Du;
  std::memcpy(&x0, &x0_bits, 4);
  std::string crlf_header =
      ply_header("binary_little_endian", 2, "property float x\nproperty float y\nproperty float z\n");
  for (std::size_t at = 0; (at = crlf_header.find('\n', at)) != std::string::npos; at += 2)
    crlf_header.insert(at, "\r");
  CHECK(same_bits(parse("crlf.ply", crlf_header + crlf.bytes), {Point3{x0, 2, 3}, Point3{4, 5, 6}}));
  const std::string crlf_ascii =
      "ply\r\nformat ascii 1.0\r\nelement vertex 2\r\nproperty float x\r\n"
      "property float y\r\nproperty float z\r\nend_header\r\n1 2 3\r\n\r\n4 5 6\r\n";
  CHECK(same_bits(parse("crlf_ascii.ply", crlf_ascii), {Point3{1, 2, 3}, Point3{4, 5, 6}}));
}

TEST_CASE("ply: bad files name the file and the line, element or byte offset", "[io]") {
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  const std::string le = "binary_little_endian";
  const std::string two = Body{}.xyz(1, 2, 3).xyz(4, 5, 6).bytes;
  struct Case {
    std::string bytes, detail;
  };
  const Case cases[] = {
      {ply_header(le, 2, xyz) + two.substr(0, 20),
       "truncated PLY file: element 'vertex' 1 of 2, property 'z' needs 4 bytes at byte offset"},
      {ply_header(le, 3, xyz) + two, "element 'vertex' 2 of 3, property 'x' needs 4 bytes"},
      {ply_header(le, 1, xyz) + two, "12 bytes after the last element (from byte offset"},
      {ply_header("ascii", 3, xyz) + "1 2 3\n4 5 6\n", "the data ends after 2 of 3 entries of element 'vertex'"},
      {ply_header("ascii", 1, xyz) + "1 2 3\n4 5 6\n", ":9: corrupt PLY data: a line after the last element"},
      {ply_header("ascii", 1, xyz) + "1 2 3 4\n",
       ":8: corrupt PLY data: element 'vertex' 0 has 4 values on its line, 3 expected"},
      {ply_header("ascii", 1, xyz) + "1 2\n",
       ":8: corrupt PLY data: the line ends before element 'vertex' 0, property 'z'"},
      {ply_header("ascii", 1, xyz) + "1 2 abc\n",
       ":8: corrupt PLY data: element 'vertex' 0, property 'z': 'abc' is not a valid float32"},
      {ply_header("ascii", 1, "property uchar x\nproperty float y\nproperty float z\n") + "256 2 3\n",
       "'256' is not a valid uint8"},
      {ply_header(le, 1, "property list int float e\n" + xyz) + Body{}.put<std::int32_t>(-1).xyz(1, 2, 3).bytes,
       "list 'e' has a negative count (-1) at byte offset"},
      {ply_header("ascii", 1, "property list int float e\n" + xyz) + "-1 1 2 3\n",
       "list count '-1' is not a int32 count"},
      {ply_header("ascii", 1, "property list uchar float e\n" + xyz) + "5 1 2 3\n",
       "a list of 5 items but the line holds 3 more values"},
      {ply_header(le, 1, "property list uint float e\n" + xyz) +
           Body{}.put<std::uint32_t>(0xFFFFFFFFu).xyz(1, 2, 3).bytes,
       "property 'e' needs 17179869180 bytes"},
      {ply_header("ascii", 1, "property list float float e\n" + xyz) + "0 1 2 3\n",
       ":4: corrupt PLY header: a list count must be of an integer type, not 'float'"},
      {ply_header("ascii", 1, "property float16 x\n") + "1\n",
       ":4: corrupt PLY header: unknown property type 'float16'"},
      {ply_header("ascii", 1, "property double x\nproperty double y\nproperty double z\n") + "1 1e300 3\n",
       ":8: vertex 0 'y' = 1.0000000000000001e+300 is beyond the float32 range"},
      {ply_header(le, 1, "property double x\nproperty double y\nproperty double z\n") +
           Body{}.put(1.0).put(-1e39).put(3.0).bytes,
       "vertex 0 (byte offset 126): 'y' = -9.9999999999999994e+38 is beyond the float32 range"},
      {ply_header("ascii", 1, "property list uchar float x\nproperty float y\nproperty float z\n") + "1 1 2 3\n",
       ":3: the vertex property 'x' is a list"},
      {ply_header("ascii", 1, "property float x\nproperty float y\n") + "1 2\n",
       ":3: the vertex element has no 'z' property"},
      {ply_header("ascii", 1, xyz + "property float x\n") + "1 2 3 4\n",
       ":7: corrupt PLY header: property 'x' appears twice in element 'vertex'"},
      {"ply\nformat ascii 1.0\nelement vertex 1\n" + xyz + "element vertex 1\n" + xyz + "end_header\n1 2 3\n1 2 3\n",
       ":7: corrupt PLY header: a second element 'vertex'"},
      {"ply\nelement vertex 1\n" + xyz + "end_header\n1 2 3\n",
       ":2: corrupt PLY header: an element before the format line"},
      {"ply\nformat ascii 2.0\nelement vertex 1\n" + xyz + "end_header\n1 2 3\n",
       ":2: corrupt PLY header: expected 'format ascii|"},
      {"ply\nformat ascii 1.0\n\nelement vertex 1\n" + xyz + "end_header\n1 2 3\n",
       ":3: corrupt PLY header: an empty line"},
      {"ply\nformat ascii 1.0\nelement vertex 1\n" + xyz + "end_header now\n1 2 3\n",
       ":7: corrupt PLY header: words after end_header"},
      {"ply\nformat ascii 1.0\nelement face 1\nproperty int a\nend_header\n1\n", "the PLY file has no vertex element"},
      {"ply\nformat ascii 1.0\nelement vertex 1\n" + xyz, "no end_header line"},
      {"PLY\n", "not a PLY file"},
      {ply_header(le, 4294967295u, xyz) + two, ":3: too many points (4294967295; at most 2^32 - 2)"},
      {ply_header("ascii", 0, xyz), ":3: the point cloud is empty (element vertex 0)"},
  };
  int i = 0;
  for (const Case& c : cases) {
    require_parse_error("bad" + std::to_string(i++) + ".ply", c.bytes, c.detail);
  }
}

TEST_CASE("pcd: versions, field types and counts, organized clouds, every DATA kind", "[io]") {
  // v0.6 without POINTS (WIDTH x HEIGHT), integer and float64 coordinates, a COUNT 3 field
  // before x, U8 and I2 fields, a repeated padding name.
  const std::string v06 =
      "# .PCD v.6\nVERSION .6\nFIELDS n x _ y z _\nSIZE 4 8 1 2 4 1\nTYPE F F U I U U\n"
      "COUNT 3 1 1 1 1 2\nWIDTH 2\nHEIGHT 2\nDATA ascii\n"
      "0 0 nan 1.5 7 -2 3 0 0\n1 1 1 0.1 0 32767 4294967295 1 1\n"
      "\n0 0 0 -0 255 -32768 0 2 2\n0 0 0 1e-45 0 0 16777217 3 3\n";
  CHECK(same_bits(parse("v06.pcd", v06), {Point3{1.5f, -2, 3}, Point3{0.1f, 32767, 4294967296.0f},
                                          Point3{-0.0f, -32768, 0}, Point3{1e-45f, 0, 16777216.0f}}));
  // The same points as binary (little-endian records) and binary_compressed (field after
  // field, LZF), POINTS only, VERSION 0.7 in another keyword order, CRLF header.
  const std::string header =
      "VERSION 0.7\r\nFIELDS n x _ y z _\r\nSIZE 4 8 1 2 4 1\r\nTYPE F F U I U U\r\n"
      "COUNT 3 1 1 1 1 2\r\nVIEWPOINT 0 0 0 1 0 0 0\r\nPOINTS 4\r\nDATA ";
  const double xs[4] = {1.5, 0.1, -0.0, 1e-45};
  const std::int16_t ys[4] = {-2, 32767, -32768, 0};
  const std::uint32_t zs[4] = {3, 4294967295u, 0, 16777217};
  Body rec;
  for (int i = 0; i < 4; ++i)
    rec.put(0.0f).put(0.0f).put(0.0f).put(xs[i]).put<std::uint8_t>(0).put(ys[i]).put(zs[i]).put<std::uint16_t>(0);
  const PointCloud expected = parse("v06.pcd", v06);
  CHECK(same_bits(parse("binary.pcd", header + "binary\r\n" + rec.bytes), expected));
  Body cols;
  for (int i = 0; i < 12; ++i) cols.put(0.0f);
  for (double x : xs) cols.put(x);
  for (int i = 0; i < 4; ++i) cols.put<std::uint8_t>(9);
  for (auto y : ys) cols.put(y);
  for (auto z : zs) cols.put(z);
  for (int i = 0; i < 4; ++i) cols.put<std::uint16_t>(9);
  const std::string packed = lzf_literals(cols.bytes);
  const std::string compressed = header + "binary_compressed\r\n" + u32_le(static_cast<std::uint32_t>(packed.size())) +
                                 u32_le(static_cast<std::uint32_t>(cols.bytes.size())) + packed;
  CHECK(same_bits(parse("compressed.pcd", compressed), expected));
  // WIDTH alone (HEIGHT 1), no VERSION, no COUNT, comments.
  CHECK(
      same_bits(parse("width.pcd", "# hi\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n# there\nWIDTH 1\nDATA ascii\n1 2 3\n"),
                {Point3{1, 2, 3}}));
}

TEST_CASE("pcd: bad files name the file and the line or byte offset", "[io]") {
  const std::string head = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n";
  const std::string two = Body{}.xyz(1, 2, 3).xyz(4, 5, 6).bytes;
  const std::string compressed_head = head + "POINTS 2\nDATA binary_compressed\n";
  const std::string good_block = lzf_literals(two);
  struct Case {
    std::string bytes, detail;
  };
  const Case cases[] = {
      {head + "WIDTH 2\nHEIGHT 2\nPOINTS 3\nDATA ascii\n",
       ":6: corrupt PCD header: WIDTH x HEIGHT (2 x 2) differs from POINTS (3)"},
      {head + "HEIGHT 2\nPOINTS 2\nDATA ascii\n", ":4: corrupt PCD header: HEIGHT without WIDTH"},
      {head + "DATA ascii\n1 2 3\n", ":4: corrupt PCD header: neither WIDTH nor POINTS given"},
      {head + "POINTS 1\nDATA binary\n" + two, "12 bytes after the last point (from byte offset 68)"},
      {head + "POINTS 3\nDATA binary\n" + two,
       "truncated PCD file: 3 points of 12 bytes need 36 bytes of binary data from byte offset 56"},
      {head + "POINTS 1\nDATA ascii\n1 2 3\n4 5 6\n", ":7: corrupt PCD data: a line after the last point"},
      {head + "POINTS 2\nDATA ascii\n1 2 3\n", "truncated PCD file: the data ends after 1 of 2 points"},
      {head + "POINTS 1\nDATA ascii\n1 2\n", ":6: corrupt PCD data: point 0 has 2 values, the header announces 3"},
      {head + "POINTS 1\nDATA ascii\n1 0x2 3\n",
       ":6: corrupt PCD data: point 0, field 'y': '0x2' is not a valid float32"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 3 1 1\nPOINTS 1\nDATA ascii\n1 1 1 2 3\n",
       ":4: field 'x' has COUNT 3"},
      {"FIELDS x y w\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n", ":1: the file has no 'z' field"},
      {"FIELDS x y z x\nSIZE 4 4 4 4\nTYPE F F F F\nPOINTS 1\nDATA ascii\n1 2 3 4\n",
       ":1: corrupt PCD header: field 'x' appears twice"},
      {"FIELDS x y z\nSIZE 4 3 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n",
       ":2: corrupt PCD header: SIZE '3' of field 'y'"},
      {"FIELDS x y z\nSIZE 4 2 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n",
       ":3: corrupt PCD header: TYPE 'F' of field 'y' with SIZE 2"},
      {"FIELDS x y z\nSIZE 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n",
       ":2: corrupt PCD header: SIZE lists 2 values for 3 fields"},
      {"SIZE 4 4 4\nFIELDS x y z\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2 3\n",
       ":1: corrupt PCD header: SIZE before FIELDS"},
      {head + "FIELDS x y z\nPOINTS 1\nDATA ascii\n1 2 3\n", ":4: corrupt PCD header: a second FIELDS line"},
      {"VERSION 0.8\n" + head + "POINTS 1\nDATA ascii\n1 2 3\n", ":1: unsupported PCD VERSION"},
      {head + "POINTS 1\nDATA text\n1 2 3\n",
       ":5: corrupt PCD header: DATA must be ascii, binary or binary_compressed"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 2" + std::string(1, '\0') + " 3\n",
       ":6: corrupt PCD data: a control character"},
      {"FIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 1e300 3\n",
       "point 0 (line 6): 'y' = 1.0000000000000001e+300 is beyond the float32 range"},
      {compressed_head + u32_le(static_cast<std::uint32_t>(good_block.size())) + u32_le(20) + good_block,
       "the compressed block decompresses to 20 bytes, but 2 points of 12 bytes take 24"},
      {compressed_head + u32_le(1000) + u32_le(24) + good_block, "passes the end of the file"},
      {compressed_head + u32_le(static_cast<std::uint32_t>(good_block.size())) + u32_le(24) + good_block + "xx",
       "2 bytes after the compressed block"},
      {compressed_head + u32_le(3) + u32_le(24) + std::string("\x00\x01\x20\x05", 3), "is corrupt"},
      {compressed_head + u32_le(4) + u32_le(24) + std::string("\x00\x01\x20\x05", 4),
       "the LZF data at byte offset 75 is corrupt"},  // a reference before the output's start
      {compressed_head + u32_le(2) + u32_le(24) + std::string("\x00\x01", 2), "decompresses to 1 bytes, not 24"},
      {compressed_head + u32_le(0) + u32_le(24), "0 compressed bytes cannot hold 24 bytes"},
      {compressed_head + "\x01\x00", "needs 8 bytes of sizes"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 0\nDATA ascii\n", "the point cloud is empty (POINTS 0)"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 4294967295\nDATA binary\n" + two, "too many points"},
      {"FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\n", "no complete DATA line"},
      {"hello\n", "not a PCD file"},
  };
  int i = 0;
  for (const Case& c : cases) require_parse_error("bad" + std::to_string(i++) + ".pcd", c.bytes, c.detail);
}

TEST_CASE("lzf: decompression checks every bound", "[io]") {
  auto run = [](const std::string& in, std::size_t capacity) {
    std::vector<unsigned char> out(capacity + 1, 0xEE);
    const long n =
        tigris::lzf_decompress(reinterpret_cast<const unsigned char*>(in.data()), in.size(), out.data(), capacity);
    CHECK(out[capacity] == 0xEE);  // never past the capacity
    return n < 0 ? std::string("error") : std::string(out.begin(), out.begin() + n);
  };
  CHECK(run(std::string("\x02"
                        "abc",
                        4),
            3) == "abc");
  CHECK(run(std::string("\x01"
                        "ab"
                        "\x20\x01",
                        5),
            5) == "ababa");  // an overlapping reference
  // A long reference: length 7 + 3 + 2 = 12 bytes, one back.
  CHECK(run(std::string("\x00"
                        "z"
                        "\xE0\x03\x00",
                        5),
            13) == std::string(13, 'z'));
  CHECK(run(std::string("\x02"
                        "abc",
                        4),
            2) == "error");  // output full
  CHECK(run(std::string("\x05"
                        "ab",
                        3),
            10) == "error");  // literal run past the input
  CHECK(run(std::string("\x00"
                        "a"
                        "\x20",
                        3),
            10) == "error");  // reference cut off
  CHECK(run(std::string("\x00"
                        "a"
                        "\xE0",
                        3),
            10) == "error");  // long reference cut off
  CHECK(run(std::string("\x00"
                        "a"
                        "\xE0\x01",
                        4),
            10) == "error");  // ... after its length byte
  CHECK(run(std::string("\x00"
                        "a"
                        "\x20\x01",
                        4),
            10) == "error");  // two back from one byte
  CHECK(run(std::string("\x00"
                        "a"
                        "\x20\x00",
                        4),
            3) == "error");  // 3 more bytes do not fit
  CHECK(run("", 10).empty());
}

TEST_CASE("results CSV: read back what --dump-results writes", "[io]") {
  tigris::Results r;
  const std::vector<tigris::Neighbor> q0 = {{17, 0.0f}, {3, 0.25f}, {5, 0.25f}}, q2 = {{4, 1e-40f}};
  r.append_query(q0.data(), q0.data() + q0.size());
  r.append_query(nullptr, nullptr);  // no neighbour: no row
  r.append_query(q2.data(), q2.data() + q2.size());
  r.append_query(nullptr, nullptr);
  std::ostringstream csv;
  tigris::write_results_csv(csv, r);
  const std::string text = csv.str();
  auto same = [](const tigris::Results& a, const tigris::Results& b) {
    if (a.offset != b.offset) return false;
    for (std::size_t i = 0; i < a.neighbors.size(); ++i)
      if (a.neighbors[i].index != b.neighbors[i].index || bits(a.neighbors[i].dist2) != bits(b.neighbors[i].dist2))
        return false;
    return true;
  };
  CHECK(same(tigris::parse_results_csv(text.data(), text.size(), "r.csv", 4), r));
  const tigris::Results inferred = tigris::parse_results_csv(text.data(), text.size(), "r.csv");
  CHECK(inferred.num_queries() == 3);  // the trailing query without rows is not in the file
  struct Case {
    std::string text, detail;
  };
  const std::string h = "query,rank,index,dist2\n";
  const Case cases[] = {
      {"", "r.csv:1: expected the header"},
      {h + "0,1,3,0.5\n", "r.csv:2: rank 1 of query 0 (expected 0)"},
      {h + "1,0,3,0.5\n0,0,3,0.5\n", "r.csv:3: query 0 after query 1"},
      {h + "0,0,3,0.5\n0,1,2,0.25\n", "r.csv:3: neighbours of query 0 out of canonical (dist2, index) order"},
      {h + "0,0,3,0.5\n0,1,3,0.5\n", "r.csv:3: neighbours of query 0 out of canonical"},
      {h + "0,0,3,0.5\n0,1,3,0.75\n", "r.csv:3: index 3 appears twice in query 0"},
      {h + "0,0,3,0.5\n1,0,3,0.75\n3,0,3,0.75\n", ""},
      {h + "0,0,3,-0.5\n", "r.csv:2: expected 'query,rank,index,dist2'"},
      {h + "0,0,3,nan\n", "r.csv:2: expected"},
      {h + "0,0,3,1e39\n", "r.csv:2: expected"},
      {h + "0,0,3, 1\n", "r.csv:2: expected"},
      {h + "0,0,4294967295,1\n", "r.csv:2: index 4294967295 out of range"},
      {h + "99999999,0,3,1\n", "r.csv:2: query 99999999 beyond 16777216 queries"},
  };
  for (const Case& c : cases) {
    INFO(c.text);
    if (c.detail.empty()) {  // valid
      CHECK(tigris::parse_results_csv(c.text.data(), c.text.size(), "r.csv").num_queries() == 4);
      continue;
    }
    CHECK_THROWS_WITH(tigris::parse_results_csv(c.text.data(), c.text.size(), "r.csv"), Catch::Contains(c.detail));
  }
  CHECK_THROWS_WITH(tigris::parse_results_csv(text.data(), text.size(), "r.csv", 2),
                    Catch::Contains("query 2 beyond the 2 queries"));
}

TEST_CASE("ply and pcd: large headers and data stay linear", "[io]") {
  // 200000 elements before the vertex element, 200000 properties in it: parsed in well under a
  // second (name checks are hash lookups, not scans).
  std::string ply = "ply\nformat binary_little_endian 1.0\n";
  for (int i = 0; i < 200000; ++i) ply += "element e" + std::to_string(i) + " 0\n";
  ply += "element vertex 1\n";
  for (int i = 0; i < 200000; ++i) ply += "property uchar p" + std::to_string(i) + "\n";
  ply += "property float x\nproperty float y\nproperty float z\nend_header\n";
  ply += std::string(200000, '\0') + Body{}.xyz(1, 2, 3).bytes;
  const auto start = std::chrono::steady_clock::now();
  CHECK(same_bits(parse("wide.ply", ply), {Point3{1, 2, 3}}));
  std::string pcd = "FIELDS";
  for (int i = 0; i < 200000; ++i) pcd += " f" + std::to_string(i);
  pcd += " x y z\nSIZE";
  for (int i = 0; i < 200003; ++i) pcd += " 4";
  pcd += "\nTYPE";
  for (int i = 0; i < 200003; ++i) pcd += " F";
  pcd += "\nPOINTS 1\nDATA binary\n" + std::string(800000, '\0') + Body{}.xyz(4, 5, 6).bytes;
  CHECK(same_bits(parse("wide.pcd", pcd), {Point3{4, 5, 6}}));
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(5));
}
