#include "out_folder.hpp"

#include <fcntl.h>
#include <fnmatch.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <ext/stdio_filebuf.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "arg_checks.hpp"
#include "build_info.hpp"
#include "children.hpp"
#include "digest.hpp"
#include "input_file.hpp"
#include "json_file.hpp"

namespace tigris {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kManifest = "manifest.json";
constexpr const char* kTmpPrefix = ".tigris-tmp-";

std::string utc_now() {
  char b[32];
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return b;
}

bool matches(const std::vector<std::string>& patterns, const std::string& name) {
  for (std::string p : patterns) {
    if (!p.empty() && p.back() == '/') p.pop_back();
    if (::fnmatch(p.c_str(), name.c_str(), FNM_PERIOD) == 0) return true;
  }
  return false;
}

std::vector<std::string> strings_of(const json& j) {
  std::vector<std::string> v;
  if (j.is_array())
    for (const json& s : j)
      if (s.is_string()) v.push_back(s.get<std::string>());
  return v;
}

std::string short_dump(const json& j) {
  std::string s = j.dump();
  return s.size() > 80 ? s.substr(0, 77) + "..." : s;
}

// What differs between an earlier run's record and this one's, a line each.
std::vector<std::string> changes(const json& old, const FolderSpec& now) {
  std::vector<std::string> out;
  const json& before = old.contains("settings") ? old["settings"] : json::object();
  std::set<std::string> keys;
  for (const auto& [k, v] : before.items()) keys.insert(k);
  for (const auto& [k, v] : now.settings.items()) keys.insert(k);
  for (const std::string& k : keys) {
    const json a = before.contains(k) ? before[k] : json("(none)");
    const json b = now.settings.contains(k) ? now.settings[k] : json("(none)");
    if (a != b) out.push_back("settings." + k + ": " + short_dump(a) + " -> " + short_dump(b));
  }
  std::map<std::string, json> was;
  if (old.contains("inputs") && old["inputs"].is_array())
    for (const json& in : old["inputs"])
      if (in.is_object() && in.contains("role")) was[in["role"].dump()] = in;
  std::set<std::string> seen;
  for (const json& in : now.inputs) {
    const std::string role = in.value("role", "input");
    const std::string key = in["role"].dump();
    seen.insert(key);
    const auto it = was.find(key);
    const std::string what = "input " + role + (in.contains("path") ? " (" + in["path"].get<std::string>() + ")" : "");
    if (it == was.end())
      out.push_back(what + ": not an input of the earlier run");
    else if (it->second.value("path", "") != in.value("path", "") &&
             !(in.contains("sha256") && it->second.value("sha256", std::string()) == in["sha256"].get<std::string>()))
      // The same bytes under another path (a moved prefix's preset, a copied input) are the same input.
      out.push_back(what + ": the earlier run read " + it->second.value("path", std::string("a built-in input")));
    else if (json a = it->second, b = in; a.erase("path"), b.erase("path"), a != b)
      out.push_back(what + ": content changed (" + std::to_string(it->second.value("bytes", 0ull)) + " -> " +
                    std::to_string(in.value("bytes", 0ull)) + " bytes, sha256 " +
                    it->second.value("sha256", std::string("-")).substr(0, 12) + " -> " +
                    in.value("sha256", std::string("-")).substr(0, 12) + ")");
  }
  for (const auto& [key, in] : was)
    if (!seen.count(key)) out.push_back("input " + in.value("role", std::string("?")) + ": no longer an input");
  return out;
}

std::string listed(const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t i = 0; i < names.size() && i < 5; ++i) s += (i ? ", " : "") + names[i];
  if (names.size() > 5) s += " and " + std::to_string(names.size() - 5) + " more";
  return s;
}

// The top-level name under `dir` of `file` ("" when it lies outside), links and ".." resolved.
std::string top_in_folder(const std::string& dir, const std::string& file) {
  std::error_code ec;
  const fs::path root = fs::weakly_canonical(fs::absolute(dir), ec);
  const fs::path rel = fs::weakly_canonical(fs::absolute(file), ec).lexically_relative(root);
  return rel.empty() || *rel.begin() == ".." || rel == "." ? "" : rel.begin()->string();
}

std::string absolute_path(const std::string& file) {
  std::error_code ec;
  return fs::weakly_canonical(fs::absolute(file), ec).string();
}

// Size and modification time: how the next run knows a file as one this command wrote.
json file_identity(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return nullptr;
  return {{"bytes", static_cast<std::uint64_t>(st.st_size)},
          {"mtime_ns", static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec}};
}

// Whether an earlier run's command line (`old`'s argv, run in its cwd) named `abs` with `flag`
// ("--vcd (GTKWave save file)" counts as --vcd's): how a manifest written before the "written"
// record knows its files.
bool named_by(const json& old, const std::string& flag, const std::string& abs) {
  if (!old.is_object() || !old.contains("argv") || !old["argv"].is_array()) return false;
  const std::string name = flag.substr(0, flag.find(' '));
  const fs::path cwd = old.value("cwd", std::string());
  const std::vector<std::string> argv = strings_of(old["argv"]);
  const auto same = [&](const std::string& p) {
    std::error_code ec;
    return fs::weakly_canonical(fs::path(p).is_absolute() ? fs::path(p) : cwd / p, ec).string() == abs;
  };
  for (std::size_t i = 0; i < argv.size(); ++i) {
    if (argv[i] == name && i + 1 < argv.size() && same(argv[i + 1])) return true;
    if (argv[i].rfind(name + "=", 0) == 0 && same(argv[i].substr(name.size() + 1))) return true;
  }
  return false;
}

// Write ends of named pipes held open from the claim to the end of the process: the reader
// then sees one stream, and its end only when the command is done.
std::vector<int>& held_pipes() {
  static std::vector<int> fds;
  return fds;
}

// The descriptor a stream path names: /dev/stdout 1, /dev/stderr 2, /dev/fd/N and
// /proc/self/fd/N N; -1 for any other path.
int stream_fd(const std::string& path) {
  const std::string p = fs::path(path).lexically_normal().string();
  if (p == "/dev/stdout") return 1;
  if (p == "/dev/stderr") return 2;
  for (const char* prefix : {"/dev/fd/", "/proc/self/fd/"}) {
    const std::string pre = prefix;
    if (p.size() > pre.size() && p.compare(0, pre.size(), pre) == 0 &&
        p.find_first_not_of("0123456789", pre.size()) == std::string::npos)
      return std::atoi(p.c_str() + pre.size());
  }
  return -1;
}

std::vector<std::string>& command_line_record() {
  static std::vector<std::string> argv;
  return argv;
}

}  // namespace

bool is_stream_path(const std::string& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // through links: /dev/stdout may be a pipe
  return stream_fd(path) >= 0 || fs::path(path).lexically_normal() == "/dev/null" ||
         (fs::exists(st) && !fs::is_regular_file(st) && !fs::is_directory(st));
}

std::string temp_path_for(const std::string& path) {
  if (is_stream_path(path)) return path;
  const fs::path p(path);
  return (p.parent_path() / (std::string(kTmpPrefix) + p.filename().string() + "-" + std::to_string(::getpid())))
      .string();
}

void record_command_line(int argc, char** argv) { command_line_record().assign(argv, argv + argc); }

std::vector<std::string> parent_outputs() {
  std::vector<std::string> v;
  const char* env = std::getenv("TIGRIS_PARENT_OUTPUTS");
  std::istringstream in(env ? env : "");
  for (std::string w; in >> w;) v.push_back(w);
  return v;
}

OutFolder::OutFolder(const std::string& dir, FolderSpec spec) : dir_(dir), spec_(std::move(spec)) {
  const std::string what = "--out " + dir_;
  if (dir_.empty()) throw std::invalid_argument("--out: give a folder");
  // The parent's files are named for this process only: its own children get none.
  const std::vector<std::string> parents = parent_outputs();
  ::unsetenv("TIGRIS_PARENT_OUTPUTS");
  std::error_code ec;
  const fs::file_status st = fs::status(dir_, ec);
  if (fs::exists(st) && !fs::is_directory(st)) throw std::invalid_argument(what + ": exists and is not a folder");
  const bool created = !fs::exists(st);  // a refused claim removes a folder it made
  fs::create_directories(dir_, ec);
  if (ec) throw std::invalid_argument(what + ": cannot create the folder: " + ec.message());
  fd_ = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) throw std::invalid_argument(what + ": cannot open the folder: " + std::strerror(errno));
  const std::optional<json> old = lock_and_read();
  try {
    claim(old, parents);
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    if (created && fs::is_empty(dir_, ec)) fs::remove(dir_, ec);
    throw;
  }
}

// The folder locked, then the earlier run's manifest (none: a new folder); a folder another
// run holds is refused naming that run.
std::optional<json> OutFolder::lock_and_read() {
  const std::string manifest_path = path(kManifest);
  const auto read_old = [&]() -> std::optional<json> {
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(manifest_path, ec))) return std::nullopt;
    return parse_json_text(read_input(manifest_path, "the folder's manifest", kMaxSettingsBytes), manifest_path);
  };
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    std::string holder;
    try {
      const std::optional<json> old = read_old();
      if (old && old->is_object() && old->contains("pid"))
        holder = " (tigris " + old->value("command", std::string("?")) + ", pid " + (*old)["pid"].dump() + ")";
    } catch (const std::exception&) {
    }
    throw std::invalid_argument("--out " + dir_ + ": another run is writing into this folder" + holder +
                                "; wait until it has finished, or use another --out");
  }
  try {
    return read_old();
  } catch (const std::exception& e) {
    ::close(fd_);
    fd_ = -1;
    throw std::invalid_argument(std::string(e.what()) + "; this folder's record is unreadable: use another --out");
  }
}

// Claims the locked folder over the earlier run's record `old`: refuses what would lose data,
// clears or keeps the earlier outputs (resume), and writes this run's manifest.
void OutFolder::claim(const std::optional<json>& old_manifest, const std::vector<std::string>& parents) {
  const std::string cmd = "tigris " + spec_.command, what = "--out " + dir_;
  const bool had_manifest = old_manifest.has_value();
  const json old = old_manifest.value_or(json());
  if (had_manifest && (!old.is_object() || old.value("tigris_manifest", 0) != 1))
    throw std::invalid_argument(path(kManifest) + ": not a tigris manifest; " + dir_ +
                                " was not written by tigris: use another --out");
  if (had_manifest && old.value("command", std::string()) != spec_.command)
    throw std::invalid_argument(what + " holds the output of tigris " + old.value("command", std::string("?")) +
                                ", not of " + cmd + ": use another --out");
  const std::vector<std::string> old_outputs = strings_of(old.is_object() ? old["outputs"] : json());
  claim_named(old, std::vector<std::string>(spec_.outputs), old_outputs);
  refuse_inputs_inside(old_outputs);
  const std::vector<std::string> ours = earlier_outputs(old_outputs, parents);
  for (const std::string& p : spec_.outputs)
    if (matches(parents, p.back() == '/' ? p.substr(0, p.size() - 1) : p))
      throw std::invalid_argument(what + ": " + p + " is the parent tool's file (TIGRIS_PARENT_OUTPUTS)");
  std::error_code ec;
  if (had_manifest && spec_.resumable) {
    const std::vector<std::string> diff = changes(old, spec_);
    if (!diff.empty()) {
      std::string msg = what + " holds a " + cmd +
                        " run with other settings or inputs, so its results would mix "
                        "with this run's:";
      for (const std::string& d : diff) msg += "\n  " + d;
      throw std::invalid_argument(msg + "\nuse another --out, or remove " + dir_ + " to start afresh");
    }
    resumed_ = !ours.empty();
  } else {
    for (const std::string& name : ours) fs::remove_all(path(name), ec);  // a fresh start
  }
  manifest_ = {{"tigris_manifest", 1},
               {"command", spec_.command},
               {"argv", spec_.argv.empty() ? command_line_record() : spec_.argv},
               {"cwd", fs::current_path(ec).string()},
               {"commit", build_commit()},
               {"settings", spec_.settings},
               {"inputs", spec_.inputs},
               {"outputs", spec_.outputs},
               {"status", "running"},
               {"pid", ::getpid()},
               {"started", utc_now()},
               {"finished", nullptr}};
  write_manifest("running");
  set_rerun_note(spec_.resumable);
}

// An input inside the folder under a name this run (or the earlier one) writes would be
// overwritten or removed.
void OutFolder::refuse_inputs_inside(const std::vector<std::string>& old_outputs) const {
  for (const json& in : spec_.inputs) {
    if (!in.contains("path")) continue;
    const std::string top = top_in_folder(dir_, in["path"].get<std::string>());
    if (top.empty()) continue;
    if (top == kManifest || matches(spec_.outputs, top) || matches(old_outputs, top))
      throw std::invalid_argument("the input " + in.value("role", std::string("file")) + " (" +
                                  in["path"].get<std::string>() + ") lies in --out " + dir_ + " under a name tigris " +
                                  spec_.command + " writes (" + top +
                                  "): move it out of the folder, or use another --out");
  }
}

// The earlier run's outputs in the folder; a file no tigris run wrote there is refused (a killed
// run's half-written file is removed, the parent's files and the user's companions stay).
std::vector<std::string> OutFolder::earlier_outputs(const std::vector<std::string>& old_outputs,
                                                    const std::vector<std::string>& parents) const {
  std::vector<std::string> foreign, ours;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir_, ec)) {
    const std::string name = e.path().filename().string();
    if (name == kManifest || matches(parents, name)) continue;
    if (name.rfind(kTmpPrefix, 0) == 0) {  // a killed run's half-written file
      fs::remove_all(e.path(), ec);
      continue;
    }
    if (std::find(kept_.begin(), kept_.end(), name) != kept_.end()) continue;  // the user's companion
    (matches(old_outputs, name) ? ours : foreign).push_back(name);
  }
  std::sort(foreign.begin(), foreign.end());
  if (!foreign.empty())
    throw std::invalid_argument("--out " + dir_ + " holds " + (foreign.size() == 1 ? "a file" : "files") + " tigris " +
                                spec_.command + " did not write (" + listed(foreign) + "): use a new or empty folder");
  return ours;
}

void OutFolder::claim_named(const json& old, const std::vector<std::string>& fixed_outputs,
                            const std::vector<std::string>& old_outputs) {
  const bool has_record = old.is_object() && old.contains("written") && old["written"].is_array();
  const json old_written = has_record ? old["written"] : json::array();
  // Records of the earlier runs' files still as they were: carried into this run's record, so a
  // later run naming them again knows them (this run's own outputs replace theirs).
  for (const json& w : old_written)
    if (w.is_object() && w.contains("path") && w.value("file", json()) == file_identity(w.value("path", std::string())))
      carried_.push_back(w);
  const std::string cmd = "tigris " + spec_.command, what = "--out " + dir_;
  std::vector<PathUse> ins, outs;
  for (const json& in : spec_.inputs)
    if (in.contains("path")) ins.push_back({in.value("role", std::string("input")), in["path"].get<std::string>()});
  for (const NamedOutput& n : spec_.named) outs.push_back({n.flag, n.path});
  check_distinct_paths(ins, outs);  // two outputs on one file, an output on an input
  std::error_code ec;
  for (const NamedOutput& n : spec_.named) {
    if (n.path.empty()) continue;
    const std::string named = n.flag + " " + n.path;
    const std::string top = top_in_folder(dir_, n.path);
    // The manifest is the folder's record (written at the start and the end), the fixed
    // outputs are the command's own: an output under either name would be lost, or take them.
    if (top == kManifest || (!top.empty() && matches(fixed_outputs, top)))
      throw std::invalid_argument("the output " + n.path + " (" + n.flag + ") would be " + what + "'s " + top +
                                  ", which " + cmd + " writes itself: give the output another name");
    if (stream_fd(n.path) >= 0 || fs::path(n.path).lexically_normal() == "/dev/null") continue;  // set up by the caller
    const fs::file_status st = fs::symlink_status(n.path, ec);
    if (!fs::exists(st)) {
      if (!top.empty()) spec_.outputs.push_back(top);
      continue;
    }
    if (fs::is_directory(st)) throw std::invalid_argument(named + ": is a folder; name a file");
    if (fs::is_fifo(st)) {  // written as it is, once a process reads it: else tigris would wait
      const int fd = ::open(n.path.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
      if (fd < 0)
        throw std::invalid_argument(named + ": a named pipe " +
                                    (errno == ENXIO ? std::string("that no process reads") : std::strerror(errno)) +
                                    "; start its reader first, or name a file");
      held_pipes().push_back(fd);
      continue;
    }
    if (fs::is_character_file(st)) continue;  // /dev/null, a terminal
    if (!fs::is_regular_file(st) && !fs::is_symlink(st))
      throw std::invalid_argument(named + ": neither a file, a named pipe nor a device; name a file");
    // An existing file: the command's own when an earlier run into this folder wrote it and it
    // has not changed since (in the folder: by its name, unless a companion was edited); else
    // it is somebody's, and stays as it is.
    const std::string abs = absolute_path(n.path);
    const json* record = nullptr;
    for (const json& w : old_written)
      if (w.is_object() && w.value("path", std::string()) == abs) record = &w;
    const bool in_folder_ours = !top.empty() && matches(old_outputs, top);
    const bool unchanged = (record && record->value("file", json()) == file_identity(n.path)) ||
                           (!has_record && named_by(old, n.flag, abs));  // a manifest from before the record
    const bool ours = n.companion ? unchanged || (!record && in_folder_ours) : unchanged || in_folder_ours;
    if (!ours && n.companion) {
      std::fprintf(stderr,
                   "%s: note: %s is kept as it is (not written by an earlier run into %s, or changed since): "
                   "this run does not write it; remove it to get a new one\n",
                   cmd.c_str(), named.c_str(), dir_.c_str());
      // Only a companion at the folder's top is exempt from the foreign check (one deeper would
      // exempt the user's whole subfolder).
      if (!top.empty() && !fs::path(abs).lexically_relative(absolute_path(dir_)).has_parent_path())
        kept_.push_back(top);
      kept_paths_.push_back(abs);
      continue;
    }
    if (!ours)
      throw std::invalid_argument(named + ": exists and was not written by an earlier " + cmd + " into " + dir_ +
                                  " (or was changed since); remove it, or name a new file");
    if (!top.empty()) spec_.outputs.push_back(top);
  }
}

bool OutFolder::writes(const std::string& named_path) const {
  return !named_path.empty() &&
         std::find(kept_paths_.begin(), kept_paths_.end(), absolute_path(named_path)) == kept_paths_.end();
}

void OutFolder::write(const std::string& path, const std::function<void(std::ostream&)>& write) {
  write_file(path, write);
  write_manifest("running");  // its record: a run stopped from now on still knows the file as its own
}

void OutFolder::check_inputs() const {
  for (const json& in : spec_.inputs) {
    if (!in.contains("path") || !in.contains("sha256")) continue;
    const std::string path = in["path"].get<std::string>();
    std::string now;
    try {
      now = sha256_of_file(path);
    } catch (const std::exception&) {
      now = "(unreadable)";
    }
    if (now != in["sha256"].get<std::string>())
      throw std::invalid_argument("the input " + in.value("role", std::string("file")) + " (" + path +
                                  ") changed while tigris " + spec_.command + " ran (sha256 " +
                                  in["sha256"].get<std::string>().substr(0, 12) + " at the start, " +
                                  now.substr(0, 12) +
                                  " now): its results would mix two inputs, so none are written; "
                                  "run again on a file that stays as it is");
  }
}

OutFolder::~OutFolder() {
  if (fd_ < 0) return;
  if (!finished_) {
    try {
      write_manifest(stop_signal() ? "interrupted" : "failed");
    } catch (...) {
    }
  }
  ::close(fd_);
}

void OutFolder::finish(const std::string& status) {
  write_manifest(status);
  finished_ = true;
}

void OutFolder::write_manifest(const std::string& status) {
  manifest_["status"] = status;
  if (status != "running") manifest_["finished"] = utc_now();
  // What the next run into this folder may replace, kept current at every write of the record
  // (the start, each output written, the end), so that a stopped run's record has it too.
  json written = json::array();
  std::set<std::string> now;
  for (const NamedOutput& n : spec_.named)
    if (!n.path.empty() && writes(n.path) && !is_stream_path(n.path)) {
      now.insert(absolute_path(n.path));
      if (json id = file_identity(n.path); !id.is_null())
        written.push_back({{"flag", n.flag}, {"path", absolute_path(n.path)}, {"file", id}});
    }
  for (const json& w : carried_)
    if (!now.count(w.value("path", std::string()))) written.push_back(w);
  manifest_["written"] = written;
  const auto text = [](const json& m) { return m.dump(2, ' ', false, json::error_handler_t::replace) + "\n"; };
  write_file(path(kManifest), [&](std::ostream& f) { f << text(manifest_); });
  // What a stop signal leaves: this record, "interrupted" (children.cpp writes it).
  json stopped = manifest_;
  stopped["status"] = "interrupted";
  set_interrupted_record(status == "running" ? fs::absolute(path(kManifest)).string() : "", text(stopped));
}

void write_file(const std::string& path, const std::function<void(std::ostream&)>& write) {
  // A descriptor the caller set up (/dev/stdout redirected to a file or a pipe) is written
  // through itself, at its own offset, after what the process printed there; once stdout is an
  // output, what the command prints afterwards goes to stderr, so the stream holds the file only.
  if (const int fd = stream_fd(path); fd >= 0) {
    std::fflush(stdout);
    const int copy = ::dup(fd);
    if (copy < 0) throw std::runtime_error(path + ": cannot write: " + std::strerror(errno));
    {
      __gnu_cxx::stdio_filebuf<char> buf(copy, std::ios::out);
      std::ostream f(&buf);
      write(f);
      f.flush();
      if (!f) throw std::runtime_error(path + ": write failed");
    }
    if (fd == 1) ::dup2(2, 1);
    return;
  }
  const fs::path parent = fs::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) fs::create_directories(parent, ec);
  // A device or pipe (/dev/null, a FIFO) is written as it is. A file is written beside its path
  // and renamed over it: a failed write leaves the old file whole, and a symbolic link is
  // replaced, never written through (it could point at an input).
  const fs::file_status st = fs::symlink_status(path, ec);
  if (fs::is_directory(st)) throw std::runtime_error(path + ": is a folder, not a file");
  const std::string tmp = temp_path_for(path);
  const bool special = tmp == path;
  {
    std::ofstream f(tmp);
    if (!f) throw std::runtime_error(path + ": cannot open for writing");
    write(f);
    f.flush();
    if (!f) {
      f.close();
      if (!special) fs::remove(tmp, ec);
      throw std::runtime_error(path + ": write failed");
    }
  }
  if (!special) {
    fs::rename(tmp, path, ec);
    if (ec) {
      std::error_code ignored;
      fs::remove(tmp, ignored);
      throw std::runtime_error(path + ": cannot write: " + ec.message());
    }
  }
}

}  // namespace tigris
