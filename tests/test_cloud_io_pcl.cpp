// The project's PCD and PLY readers (workloads/io) against PCL 1.13's on ordinary files PCL writes
// itself: every point type PCL users save, ASCII, binary and binary_compressed PCD, ASCII and
// binary PLY, organized clouds. Both must read the same x, y, z, bit for bit. And PCL reads
// what save_cloud writes. (PCL is linked by this test only: the readers do not use it.)
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <unistd.h>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>

#include "test_util.hpp"
#include "workloads/io/cloud_io.hpp"

using tigris::test::bits;
using tigris::test::same_bits;

namespace {

namespace fs = std::filesystem;
using tigris::Point3;
using tigris::PointCloud;

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("tigris_test_io_pcl_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

// Random but ordinary values: uniform, a few exact and tiny ones, negative zero.
float value(std::mt19937& rng, int i) {
  switch (i % 7) {
    case 0: return -0.0f;
    case 1: return 1e-3f * static_cast<float>(static_cast<int>(rng() % 2001) - 1000);
    default: return std::uniform_real_distribution<float>(-120.0f, 120.0f)(rng);
  }
}

template <class P>
pcl::PointCloud<P> make_cloud(std::size_t width, std::size_t height, unsigned seed) {
  std::mt19937 rng(seed);
  pcl::PointCloud<P> c;
  c.width = static_cast<std::uint32_t>(width);
  c.height = static_cast<std::uint32_t>(height);
  c.resize(width * height);
  c.width = static_cast<std::uint32_t>(width);
  c.height = static_cast<std::uint32_t>(height);
  c.is_dense = true;
  int i = 0;
  for (P& p : c.points) {
    // Every float of the point type gets a value (normals, intensity, curvature, rgb's bits).
    float* f = reinterpret_cast<float*>(&p);
    for (std::size_t k = 0; k < sizeof(P) / sizeof(float); ++k) f[k] = value(rng, i++);
    p.x = value(rng, i++);
    p.y = value(rng, i++);
    p.z = value(rng, i++);
  }
  return c;
}

// x, y, z as PCL reads the file, and as load_cloud reads it: the same bits.
void check_same(const std::string& path) {
  INFO(path);
  pcl::PointCloud<pcl::PointXYZ> theirs;
  const int status =
      fs::path(path).extension() == ".pcd" ? pcl::io::loadPCDFile(path, theirs) : pcl::io::loadPLYFile(path, theirs);
  REQUIRE(status >= 0);
  const PointCloud ours = tigris::load_cloud(path);
  REQUIRE(ours.size() == theirs.size());
  for (std::size_t i = 0; i < ours.size(); ++i) {
    INFO("point " << i);
    REQUIRE(bits(ours[i].x) == bits(theirs[i].x));
    REQUIRE(bits(ours[i].y) == bits(theirs[i].y));
    REQUIRE(bits(ours[i].z) == bits(theirs[i].z));
  }
}

template <class P>
void check_type(const TempDir& dir, const std::string& name, unsigned seed) {
  const pcl::PointCloud<P> flat = make_cloud<P>(300, 1, seed);
  const pcl::PointCloud<P> organized = make_cloud<P>(20, 15, seed + 1);
  const std::string base = dir.file(name);
  REQUIRE(pcl::io::savePCDFileASCII(base + "_ascii.pcd", flat) == 0);
  REQUIRE(pcl::io::savePCDFileBinary(base + "_binary.pcd", flat) == 0);
  REQUIRE(pcl::io::savePCDFileBinaryCompressed(base + "_compressed.pcd", flat) == 0);
  REQUIRE(pcl::io::savePCDFileBinary(base + "_organized.pcd", organized) == 0);
  REQUIRE(pcl::io::savePCDFileBinaryCompressed(base + "_organized_compressed.pcd", organized) == 0);
  REQUIRE(pcl::io::savePLYFileASCII(base + "_ascii.ply", flat) == 0);
  REQUIRE(pcl::io::savePLYFileBinary(base + "_binary.ply", flat) == 0);
  for (const char* suffix : {"_ascii.pcd", "_binary.pcd", "_compressed.pcd", "_organized.pcd",
                             "_organized_compressed.pcd", "_ascii.ply", "_binary.ply"})
    check_same(base + suffix);
}

}  // namespace

TEST_CASE("cloud_io vs PCL: the same points from the files PCL writes", "[io][pcl]") {
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
  TempDir dir;
  check_type<pcl::PointXYZ>(dir, "xyz", 1);
  check_type<pcl::PointXYZI>(dir, "xyzi", 2);
  check_type<pcl::PointXYZRGB>(dir, "xyzrgb", 3);
  check_type<pcl::PointXYZRGBA>(dir, "xyzrgba", 4);
  check_type<pcl::PointNormal>(dir, "normal", 5);
  check_type<pcl::PointXYZRGBNormal>(dir, "xyzrgbnormal", 6);
  check_type<pcl::PointXYZINormal>(dir, "xyzinormal", 7);
  check_type<pcl::PointXYZL>(dir, "xyzl", 8);
  check_type<pcl::PointWithViewpoint>(dir, "viewpoint", 9);
}

TEST_CASE("cloud_io vs PCL: PCL reads what save_cloud writes", "[io][pcl]") {
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
  TempDir dir;
  const pcl::PointCloud<pcl::PointXYZ> src = make_cloud<pcl::PointXYZ>(500, 1, 11);
  PointCloud cloud;
  for (const auto& p : src.points) cloud.push_back(Point3{p.x, p.y, p.z});
  for (const char* name : {"ours.pcd", "ours.ply"}) {
    tigris::save_cloud(dir.file(name), cloud);
    check_same(dir.file(name));
  }
}
