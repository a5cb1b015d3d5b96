// Point-cloud files (sw_ref/io/cloud_io.hpp): round trips, every kind of bad input, KITTI frames.
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
#include <stdexcept>
#include <string>
#include <vector>

#include "sw_ref/io/cloud_io.hpp"
#include "sw_ref/synthetic.hpp"

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
      const std::string name = "tigris_test_io_" + std::to_string(rd()) + "_" +
                               std::to_string(now) + "_" + std::to_string(attempt);
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

std::uint32_t bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

bool same_bits(const PointCloud& a, const PointCloud& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (bits(a[i].x) != bits(b[i].x) || bits(a[i].y) != bits(b[i].y) ||
        bits(a[i].z) != bits(b[i].z))
      return false;
  return true;
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
  for (int i = 0; i < 200; ++i)
    cloud.push_back(Point3{0.5f * i, 1.0f - 0.25f * i, 0.125f * (i % 7)});
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
  // A list property in the vertex element: PCL 1.13 shifts x, y, z into the list's values
  // (point 0 read as (7, 7, 1)) or aborts; refused with the reason (issue 11).
  const std::string list_ply = dir.file("list.ply");
  write_bytes(list_ply,
              "ply\nformat ascii 1.0\nelement vertex 4\nproperty list uint float e\nproperty float x\n"
              "property float y\nproperty float z\nend_header\n3 7 7 7 1 2 3\n1 7 10 20 30\n1 7 -5 -6 -7\n"
              "1 7 100 0 0\n");
  require_input_error(list_ply, "the vertex element has a list property ('e')");
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

  // The same policy through PCL: a NaN point in a .pcd and a .ply.
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
  require_input_error(no_z, "no 'z' field");
  const std::string int_xyz = dir.file("int_xyz.pcd");
  write_bytes(int_xyz, "FIELDS x y z\nSIZE 4 4 4\nTYPE I I I\nPOINTS 1\nDATA ascii\n1 2 3\n");
  require_input_error(int_xyz, "not float32 or float64");
  // A word that is not a number (PCL itself would read it as 0).
  const std::string word = dir.file("word.pcd");
  write_bytes(word, "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 abc 3\n");
  require_input_error(word, "not a valid number");
  // Other spellings of NaN and Inf reach validate_cloud as such.
  for (const char* value : {"inf", "-inf", "-nan", "NaN", "1e999"}) {
    const std::string path = dir.file(std::string("value") + value + ".pcd");
    write_bytes(path,
                std::string("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n1 ") +
                    value + " 3\n");
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
    for (std::size_t cut :
         {std::size_t{0}, std::size_t{3}, header_end / 2, header_end - 1, header_end,
          header_end + 7, (header_end + bytes.size()) / 2, bytes.size() - 1}) {
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
  // Headers that announce far more points than the file holds: rejected before PCL allocates.
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
  // A header keyword PCL does not know (PCL 1.13 crashes on it).
  const std::string unknown = dir.file("unknown_key.pcd");
  write_bytes(unknown,
              "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nFOO 1\nPOINTS 1\n"
              "DATA ascii\n1 2 3\n");
  require_input_error(unknown, "unknown line 'FOO'");
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
        const std::size_t span =
            trial % 3 == 1 ? std::min<std::size_t>(bytes.size(), 250) : bytes.size();
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
