#include "odometry_run.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "core/child_batch.hpp"
#include "core/digest.hpp"
#include "core/flag_values.hpp"
#include "core/timer.hpp"
#include "workloads/pose.hpp"

namespace tigris::registration {
namespace {

namespace fs = std::filesystem;
using nlohmann::ordered_json;

// A pair's registration.json: false when it is not there (the pair runs); a report that is
// there but not whole (edited, truncated; in the loop, without the accelerator's figures) is an
// error naming the file and the key.
bool read_pair(const std::string& path, bool accel, Report& out) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec))) return false;
  const std::string again = " (remove the pair's folder to register it again)";
  try {
    out = read_report(path);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(e.what() + again);
  }
  if (accel && !out.in_loop())
    throw std::invalid_argument(
        path + ": no 'accelerator', which --search accel* writes; not a whole tigris register " + "report" + again);
  return true;
}

}  // namespace

std::string frame_tag(std::size_t i) {
  char b[16];
  std::snprintf(b, sizeof b, "%06zu", i);
  return b;
}

std::vector<std::string> odometry_outputs(bool compare) {
  if (compare)
    return {"comparison.json", "flann/",          "exact/",          "approx/",         "accel/",
            "sequence/",       "flann-repeat-*/", "exact-repeat-*/", "approx-repeat-*/"};
  return {"poses.txt",  "trajectory.csv", "pairs.csv", "metrics.json", "trajectory.png",
          "errors.png", "pairs/",         "slurm/",    "sequence/"};
}

OdometryRun::OdometryRun(OdometrySettings settings, std::unique_ptr<OutFolder> claimed)
    : o(std::move(settings)), folder_(std::move(claimed)) {}

bool OdometryRun::run() {
  read_sequence();
  claim_folder();
  plan_pairs();
  if (!run_pairs()) return false;
  odometry_ = std::make_unique<Odometry>(first_, std::move(regs_), seq_.poses, o.accel);
  write_files();
  return true;
}

// The sequence's listing, poses and calibration, and the frames to register.
void OdometryRun::read_sequence() {
  seq_ = read_kitti_sequence(o.sequence);
  if (seq_.scans.size() < 2) throw std::invalid_argument(o.sequence + ": a sequence needs two frames or more");
  std::tie(first_, last_) = parse_frame_range(o.frames, seq_.scans.size());
}

// Claims OUT for a sequence given with --sequence, keyed on every input the pairs read.
void OdometryRun::claim_folder() {
  if (!folder_) {
    // A rerun resumes only with the same flags, frames and file contents (every scan of the
    // range, poses.txt and calib.txt included): changed inputs never mix with old pairs.
    nlohmann::json inputs = o.config_inputs;
    for (std::size_t i = first_; i <= last_; ++i) inputs.push_back(input_file("scan " + frame_tag(i), seq_.scans[i]));
    for (const char* name : {"poses.txt", "calib.txt"}) {
      const std::string path = o.sequence + "/" + name;
      std::error_code ec;
      if (fs::exists(fs::symlink_status(path, ec))) inputs.push_back(input_file(name, path));
    }
    FolderSpec spec{"odometry",
                    {},
                    nlohmann::json({{"sequence", fs::absolute(o.sequence).lexically_normal().string()},
                                    {"frames", {first_, last_}},
                                    {"register_flags", o.flags}}),
                    inputs,
                    odometry_outputs(false),
                    true,
                    {}};
    folder_ = std::make_unique<OutFolder>(o.out, spec);
  }
  fs::create_directories(o.out + "/pairs");
}

// Reads the pairs a run before left in OUT/pairs (a rerun resumes) and lists the rest.
void OdometryRun::plan_pairs() {
  // Each pair: frame i + 1 (source) into frame i (target), in OUT/pairs/<i>/.
  pairs_ = last_ - first_;
  regs_.resize(pairs_);
  for (std::size_t k = 0; k < pairs_; ++k)
    if (!read_pair(o.out + "/pairs/" + frame_tag(first_ + k) + "/registration.json", o.accel, regs_[k]))
      todo_.push_back(k);
  if (!seq_.note.empty()) std::fprintf(stderr, "tigris odometry: note: %s\n", seq_.note.c_str());
  std::fprintf(stderr, "tigris odometry: %s, frames %zu..%zu: %zu pairs (%zu already in %s), --jobs %d\n",
               o.sequence.c_str(), first_, last_, pairs_, pairs_ - todo_.size(), o.out.c_str(), o.jobs);
  if (const std::string job = active_array(o.out); !job.empty())
    throw std::invalid_argument("Slurm job " + job + " of an earlier submission still runs into " + o.out +
                                ": wait for it (squeue -j " + job + ") or cancel it (scancel " + job + ")");
}

// Registers the pairs to do, each a `tigris register` in OUT/pairs/<target frame>/, here or
// as one Slurm array; false: submitted with --no-wait (OUT is finished).
bool OdometryRun::run_pairs() {
  ChildBatch batch;
  batch.count = todo_.size();
  batch.dir = [&](std::size_t i) { return o.out + "/pairs/" + frame_tag(first_ + todo_[i]); };
  batch.result = "registration.json";
  batch.args = [&](std::size_t i, bool on_slurm) {
    const std::size_t k = todo_[i];
    const auto path = [&](const std::string& p) { return on_slurm ? fs::absolute(p).string() : p; };
    std::vector<std::string> args{"register", "--source", path(seq_.scans[first_ + k + 1]), "--target",
                                  path(seq_.scans[first_ + k])};
    args.insert(args.end(), o.flags.begin(), o.flags.end());
    if (!on_slurm && o.jobs > 1) args.insert(args.end(), {"--jobs", "1"});  // the pairs share the cores already
    const std::string dir = batch.dir(i);
    args.insert(args.end(), {"--out", on_slurm ? fs::absolute(dir).lexically_normal().string() : dir});
    return args;
  };
  batch.parallel = o.jobs;
  batch.slurm = o.slurm;
  batch.out = o.out;
  batch.name = "tigris-odometry";
  batch.noun = "pairs";
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t done = 0;
  std::string failure;
  const bool waited = run_batch(batch, [&](const TaskEnd& e) {
    const std::size_t k = todo_[e.k];
    const std::string dir = batch.dir(e.k), pair = frame_tag(first_ + k + 1) + " -> " + frame_tag(first_ + k);
    const bool ok =
        (e.code == 0 || e.code == 1 || !e.job.empty()) && read_pair(dir + "/" + batch.result, o.accel, regs_[k]);
    if (e.job.empty()) {  // here: a line a pair as it ends
      const double elapsed = seconds_since(t0);
      ++done;
      std::fprintf(stderr, "tigris odometry: pair %zu/%zu (%s): %s (%.0f s elapsed, about %.0f s left)\n", done,
                   todo_.size(), pair.c_str(), ok ? regs_[k].result.status.c_str() : "FAILED", elapsed,
                   elapsed / static_cast<double>(done) * static_cast<double>(todo_.size() - done));
    }
    if (!ok && failure.empty())
      failure = "pair " + pair + ": " +
                (e.job.empty() ? "tigris register exited " + std::to_string(e.code) + " (" + dir +
                                     "/log.txt: " + last_log_line(dir) + ")"
                               : "no result from Slurm job " + e.job + " (" + dir + "/log.txt: " + last_log_line(dir) +
                                     "; task logs in " + o.out + "/slurm/)");
    return failure.empty();  // here, a failure stops the scheduling
  });
  if (!waited) {
    folder_->finish("submitted");
    return false;
  }
  if (!failure.empty()) throw std::invalid_argument(failure + "; the pairs done are kept, a rerun resumes");
  return true;
}

// OUT/poses.txt, trajectory.csv, pairs.csv and metrics.json.
void OdometryRun::write_files() {
  const Odometry& odo = *odometry_;
  write_file(o.out + "/poses.txt", [&](std::ostream& f) { write_kitti_poses(f, odo.estimated(), seq_.velo_to_cam); });
  write_file(o.out + "/trajectory.csv", [&](std::ostream& f) { odo.write_trajectory_csv(f); });
  write_file(o.out + "/pairs.csv", [&](std::ostream& f) { odo.write_pairs_csv(f); });
  ordered_json& m = metrics_;
  m["command"] = "odometry";
  m["command_line"] = o.command_line;
  m["sequence"] = o.sequence;
  m["calibration"] = seq_.calibration;
  // A drive tigris synth wrote has exact poses: equal steps there are steady driving.
  const bool synthetic = fs::exists(o.sequence + "/drive.json");
  m["ground_truth_source"] = seq_.poses.empty() ? "none"
                             : synthetic        ? "exact (a synthetic drive, tigris synth: drive.json)"
                                                : "poses.txt";
  if (!seq_.note.empty()) m["sequence_note"] = seq_.note;
  m["frames"] = {first_, last_};
  m["pairs"] = pairs_;
  m["register_flags"] = o.flags;
  note_ = odo.add_metrics(m, synthetic);
  write_file(o.out + "/metrics.json",
             [&](std::ostream& f) { f << m.dump(2, ' ', false, ordered_json::error_handler_t::replace) << '\n'; });
}

}  // namespace tigris::registration
