// The one way a command owns its output folder (DESIGN 23; the contract is in
// docs/architecture.md, "The shared core"; tigris/core/folders.py is the Python twin and writes the
// same DIR/manifest.json). Construct an OutFolder after every flag and input has been checked:
// it creates or claims the folder, locks it for the run, refuses a folder holding files the
// command did not write or an input it would overwrite, and decides between resuming and a
// fresh start. Refusals are std::invalid_argument (exit 2) saying what to do instead.
#pragma once

#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tigris {

// A file a flag names (--vcd, --dump-results ...), or one derived from it (the GTKWave save file
// beside a VCD). The core claims each before any work: a reserved name of the folder, two
// outputs on one path, an output on an input, a named pipe no process reads and an existing
// file no earlier run into this folder wrote are refused. A `companion` (a documented derived
// file) that the user wrote or edited is kept, with a warning, instead of refused.
struct NamedOutput {
  std::string flag;  // "--vcd", "--vcd (GTKWave save file)"
  std::string path;  // empty: not asked for
  bool companion = false;
};

struct FolderSpec {
  std::string command;                                 // "odometry": a manifest of another command is refused
  std::vector<std::string> argv;                       // the command line, recorded
  nlohmann::json settings = nlohmann::json::object();  // what decides the results (compared on resume)
  nlohmann::json inputs = nlohmann::json::array();     // input_file() records (compared on resume)
  // What the command writes in the folder, as top-level names: "stats.json", "*.vcd", "pairs/"
  // (a folder). The next run counts these as the command's own and clears them for a fresh start.
  std::vector<std::string> outputs;
  bool resumable = false;  // a matching rerun keeps the files; a different one is refused
  // Files named by flags (--vcd, --record-trace...), claimed with the folder. One that lies in
  // the folder joins `outputs`; every one is recorded with its size and time ("written"), so
  // the next run into this folder knows it as the command's own.
  std::vector<NamedOutput> named;
};

class OutFolder {
 public:
  OutFolder(const std::string& dir, FolderSpec spec);
  ~OutFolder();  // unlocks; a run that did not finish() is recorded "failed"
  OutFolder(const OutFolder&) = delete;
  OutFolder& operator=(const OutFolder&) = delete;

  const std::string& dir() const { return dir_; }
  std::string path(const std::string& relative) const { return dir_ + "/" + relative; }
  bool resumed() const { return resumed_; }  // an earlier run's files were kept
  // False for a companion output kept because this command did not write it (warned).
  bool writes(const std::string& named_path) const;
  // Digests every input file again: one that changed since the start is an error naming it
  // (std::invalid_argument). Commands call it before they write their results.
  void check_inputs() const;
  // write_file of a flag-named output, then the record updated (the manifest's "written").
  void write(const std::string& path, const std::function<void(std::ostream&)>& write);
  // Records the end of the run in the manifest: "done", "failed", "interrupted".
  void finish(const std::string& status = "done");

 private:
  void write_manifest(const std::string& status);
  std::optional<nlohmann::json> lock_and_read();
  void claim(const std::optional<nlohmann::json>& old, const std::vector<std::string>& parents);
  void refuse_inputs_inside(const std::vector<std::string>& old_outputs) const;
  std::vector<std::string> earlier_outputs(const std::vector<std::string>& old_outputs,
                                           const std::vector<std::string>& parents) const;
  void claim_named(const nlohmann::json& old, const std::vector<std::string>& fixed_outputs,
                   const std::vector<std::string>& old_outputs);
  std::string dir_;
  FolderSpec spec_;
  nlohmann::json carried_ = nlohmann::json::array();  // earlier runs' "written" records still true
  std::vector<std::string> kept_, kept_paths_;        // companions left as the user had them (top names, paths)
  nlohmann::json manifest_;
  int fd_ = -1;
  bool resumed_ = false, finished_ = false;
};

// The process's command line, recorded by main() for every manifest.
void record_command_line(int argc, char** argv);

// The files a parent tool keeps in a child's folder (TIGRIS_PARENT_OUTPUTS, space-separated).
std::vector<std::string> parent_outputs();

// Writes `path` through `write`: into .tigris-tmp-<name>-<pid> beside it, renamed over it when
// complete, so a failed or killed write keeps the old file (or none), and a symbolic link is
// replaced, never written through; devices (/dev/null) are written directly. Creates the
// parent folder. Throws std::runtime_error naming the path when it cannot be written.
void write_file(const std::string& path, const std::function<void(std::ostream&)>& write);

// A stream the caller set up rather than a file: /dev/stdout, /dev/stderr, /dev/null,
// /dev/fd/N, /proc/self/fd/N, or (through links) a FIFO or a device. Written as it is.
bool is_stream_path(const std::string& path);
// What `path` is written through: a temporary beside it (renamed over it when whole), or the
// path itself for a stream (write_file and the VCD writer).
std::string temp_path_for(const std::string& path);

}  // namespace tigris
