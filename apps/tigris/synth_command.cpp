#include "synth_command.hpp"
#include "command.hpp"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/arg_checks.hpp"
#include "core/timer.hpp"
#include "testbench/report.hpp"
#include "workloads/io/kitti_bin.hpp"
#include "workloads/kitti_sequence.hpp"
#include "workloads/pose.hpp"

namespace tigris {
namespace {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

std::string frame_name(int i) {
  char b[32];
  std::snprintf(b, sizeof b, "%06d.bin", i);
  return b;
}

ordered_json settings_of(const DriveConfig& c) {
  // Bump the version when the drive's output changes: a rerun never mixes scans of two versions.
  return {{"generator", "tigris synth (workloads/synthetic/drive.hpp), version 1"},
          {"seed", c.seed},
          {"frames", c.frames},
          {"scanner",
           {{"rings", c.rings},
            {"azimuth_steps", c.azimuth_steps},
            {"min_range_m", c.min_range_m},
            {"max_range_m", c.max_range_m},
            {"range_noise_m", c.range_noise_m}}}};
}

// KITTI calib.txt: P0..P3 (3x4 camera matrices) and Tr (Velodyne -> cam0), 12 numbers a line.
void write_calib(std::ostream& f) {
  const char* p =
      "7.188560000000e+02 0.000000000000e+00 6.071928000000e+02 0.000000000000e+00 "
      "0.000000000000e+00 7.188560000000e+02 1.852157000000e+02 0.000000000000e+00 "
      "0.000000000000e+00 0.000000000000e+00 1.000000000000e+00 0.000000000000e+00";
  for (int i = 0; i < 4; ++i) f << 'P' << i << ": " << p << '\n';
  const Pose tr = kitti_velo_to_cam();
  char b[64];
  f << "Tr:";
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) {
      std::snprintf(b, sizeof b, " %.12e", tr(r, c));
      f << b;
    }
  f << '\n';
}

}  // namespace

void write_synthetic_drive(const DriveConfig& config, const std::string& dir, int jobs, bool quiet) {
  const ordered_json settings = settings_of(config);
  const std::string meta = dir + "/drive.json";
  // The folder's manifest is the claim: an interrupted run is completed by the next one with the
  // same settings; a folder holding anything else (a user's calib.txt) is refused.
  FolderSpec spec{"synth",
                  {},
                  nlohmann::json(settings),
                  nlohmann::json::array(),
                  {"velodyne/", "poses.txt", "calib.txt", "times.txt", "drive.json"},
                  true,
                  {}};
  OutFolder folder(dir, spec);
  write_file(meta, [&](std::ostream& f) {
    f << ordered_json{{"settings", settings}, {"complete", false}}.dump(1) << '\n';
  });
  const auto t0 = std::chrono::steady_clock::now();
  const SyntheticDrive drive(config);
  fs::create_directories(dir + "/velodyne");

  // Scans: the ones missing, `jobs` threads (each scan is independent and deterministic). A scan
  // is written beside its name and renamed when whole; leftovers of an interrupted run go.
  for (const auto& e : fs::directory_iterator(dir + "/velodyne"))
    if (e.path().filename().string().rfind(".tigris-tmp-", 0) == 0) fs::remove(e.path());
  std::vector<int> todo;
  for (int i = 0; i < config.frames; ++i)
    if (!fs::exists(dir + "/velodyne/" + frame_name(i))) todo.push_back(i);
  std::atomic<std::size_t> next{0}, done{0};
  std::mutex lock;
  std::string error;
  const auto work = [&] {
    for (std::size_t k; (k = next++) < todo.size();) {
      try {
        const PointCloud scan = drive.scan(todo[k]);
        write_file(dir + "/velodyne/" + frame_name(todo[k]), [&](std::ostream& f) { f << kitti_bin_bytes(scan); });
        std::lock_guard<std::mutex> g(lock);
        const std::size_t n = ++done;
        if (!quiet && (n == todo.size() || n % 10 == 0))
          std::fprintf(stderr, "tigris synth: %zu/%zu scans (%.0f s)\n", n, todo.size(), seconds_since(t0));
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> g(lock);
        if (error.empty()) error = e.what();
        next = todo.size();
      }
    }
  };
  std::vector<std::thread> pool;
  try {
    for (int t = 1; t < std::min<int>(jobs, static_cast<int>(todo.size())); ++t) pool.emplace_back(work);
  } catch (const std::system_error&) {  // no more threads: go on with those there are
  }
  work();
  for (std::thread& t : pool) t.join();
  if (!error.empty()) throw std::runtime_error(error);

  std::vector<Pose> poses;
  for (const DriveFrame& f : drive.frames()) {
    Pose p = Pose::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) p(r, c) = f.pose[static_cast<std::size_t>(4 * r + c)];
    poses.push_back(p);
  }
  write_file(dir + "/poses.txt", [&](std::ostream& f) { write_kitti_poses(f, poses, kitti_velo_to_cam()); });
  write_file(dir + "/calib.txt", write_calib);
  write_file(dir + "/times.txt", [&](std::ostream& f) {
    char b[32];
    for (const DriveFrame& fr : drive.frames()) {
      std::snprintf(b, sizeof b, "%e\n", fr.time_s);
      f << b;
    }
  });
  const DriveSummary& s = drive.summary();
  ordered_json m;
  m["settings"] = settings;
  m["complete"] = true;
  m["summary"] = {{"route_length_m", s.route_length_m},
                  {"crossings", s.crossings},
                  {"turns", s.turns},
                  {"stops", s.stops},
                  {"boxes_buildings_and_cars", s.buildings_and_cars},
                  {"cylinders_poles_and_trunks", s.poles_and_trunks},
                  {"spheres_tree_crowns", s.tree_crowns},
                  {"max_grade", s.max_grade},
                  {"note", "crossings, turns and stops on the way driven (from frame 0 to the last frame)"}};
  ordered_json frames = ordered_json::array();
  for (const DriveFrame& f : drive.frames())
    frames.push_back({{"time_s", f.time_s}, {"speed_m_per_s", f.speed_m_per_s}, {"distance_m", f.distance_m}});
  m["frames"] = frames;
  write_file(meta, [&](std::ostream& f) { f << m.dump(1) << '\n'; });
  folder.finish();
  if (!quiet)
    std::fprintf(stderr, "tigris synth: %s: %d frames (%zu scans cast now), %.0f m of route, %.0f s\n", dir.c_str(),
                 config.frames, todo.size(), s.route_length_m, seconds_since(t0));
}

void add_synth_options(CLI::App& app, SynthOptions& o) {
  app.add_option("--frames", o.frames, "Frames of the drive (10 Hz)")->required()->check(CLI::Range(2, 20000));
  app.add_option("--seed", o.seed, "The town's, the route's and the noise's seed (0 .. 2^64-1)")
      ->check(uint64_text())
      ->capture_default_str();
  app.add_option("--jobs", o.jobs, "Scans cast at once (threads)")->check(CLI::Range(1, 256))->capture_default_str();
  app.add_option("--out", o.out, "Output folder (KITTI layout); a rerun with the same settings completes it")
      ->required();
}

int run_synth_command(const CLI::App&, const SynthOptions& o) {
  DriveConfig c;
  c.frames = o.frames;
  c.seed = o.seed;
  write_synthetic_drive(c, o.out, o.jobs, false);
  const KittiSequence check = read_kitti_sequence(o.out);  // reads back as KITTI
  std::printf(
      "tigris synth: wrote %s: velodyne/000000.bin .. %s, poses.txt, calib.txt, times.txt, drive.json "
      "(%zu frames, seed %llu)\n",
      o.out.c_str(), frame_name(o.frames - 1).c_str(), check.scans.size(), static_cast<unsigned long long>(o.seed));
  return 0;
}

namespace {

const CommandRegistration kRegistration{options_command<SynthOptions>(
    "synth",
    "Write a synthetic drive (seeded town, 10 Hz trajectory, HDL-64E-like scans, exact poses) in "
    "KITTI's odometry layout",
    50, [](CLI::App& app, SynthOptions& o) { add_synth_options(app, o); },
    [](const CLI::App& app, SynthOptions& o, const CommandLine& /*line*/) { return run_synth_command(app, o); })};

}  // namespace
}  // namespace tigris
