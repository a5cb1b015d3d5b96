#include "out_folder.hpp"

#include <fcntl.h>
#include <fnmatch.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "build_info.hpp"
#include "children.hpp"
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
    else if (it->second.value("path", "") != in.value("path", ""))
      out.push_back(what + ": the earlier run read " + it->second.value("path", std::string("a built-in input")));
    else if (it->second != in)
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

std::vector<std::string>& command_line_record() {
  static std::vector<std::string> argv;
  return argv;
}

}  // namespace

void record_command_line(int argc, char** argv) { command_line_record().assign(argv, argv + argc); }

std::vector<std::string> parent_outputs() {
  std::vector<std::string> v;
  const char* env = std::getenv("TIGRIS_PARENT_OUTPUTS");
  std::istringstream in(env ? env : "");
  for (std::string w; in >> w;) v.push_back(w);
  return v;
}

OutFolder::OutFolder(const std::string& dir, FolderSpec spec) : dir_(dir), spec_(std::move(spec)) {
  const std::string cmd = "tigris " + spec_.command;
  const std::string what = "--out " + dir_;
  if (dir_.empty()) throw std::invalid_argument("--out: give a folder");
  // The parent's files are named for this process only: its own children get none.
  const std::vector<std::string> parents = parent_outputs();
  ::unsetenv("TIGRIS_PARENT_OUTPUTS");
  std::error_code ec;
  const fs::file_status st = fs::status(dir_, ec);
  if (fs::exists(st) && !fs::is_directory(st)) throw std::invalid_argument(what + ": exists and is not a folder");
  fs::create_directories(dir_, ec);
  if (ec) throw std::invalid_argument(what + ": cannot create the folder: " + ec.message());
  fd_ = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd_ < 0) throw std::invalid_argument(what + ": cannot open the folder: " + std::strerror(errno));
  const std::string manifest_path = path(kManifest);
  // The earlier run's record, read once the folder is ours (or to name the run that holds it).
  json old;
  bool had_manifest = false;
  const auto read_old = [&] {
    had_manifest = fs::exists(fs::symlink_status(manifest_path, ec));
    if (had_manifest)
      old = parse_json_text(read_input(manifest_path, "the folder's manifest", kMaxSettingsBytes), manifest_path);
  };
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    std::string holder;
    try {
      read_old();
      if (old.is_object() && old.contains("pid"))
        holder = " (tigris " + old.value("command", std::string("?")) + ", pid " + old["pid"].dump() + ")";
    } catch (const std::exception&) {
    }
    throw std::invalid_argument(what + ": another run is writing into this folder" + holder +
                                "; wait until it has finished, or use another --out");
  }
  try {
    read_old();
  } catch (const std::exception& e) {
    ::close(fd_);
    fd_ = -1;
    throw std::invalid_argument(std::string(e.what()) + "; this folder's record is unreadable: use another --out");
  }
  try {
    if (had_manifest && (!old.is_object() || old.value("tigris_manifest", 0) != 1))
      throw std::invalid_argument(manifest_path + ": not a tigris manifest; " + dir_ +
                                  " was not written by tigris: use another --out");
    if (had_manifest && old.value("command", std::string()) != spec_.command)
      throw std::invalid_argument(what + " holds the output of tigris " + old.value("command", std::string("?")) +
                                  ", not of " + cmd + ": use another --out");
    const std::vector<std::string> old_outputs = strings_of(old.is_object() ? old["outputs"] : json());
    const fs::path root = fs::weakly_canonical(fs::absolute(dir_), ec);
    const auto top_in_folder = [&](const std::string& file) -> std::string {
      const fs::path rel = fs::weakly_canonical(fs::absolute(file), ec).lexically_relative(root);
      return rel.empty() || *rel.begin() == ".." || rel == "." ? "" : rel.begin()->string();
    };
    for (const std::string& f : spec_.also_written) {
      const std::string top = f.empty() ? "" : top_in_folder(f);
      if (top.empty()) continue;
      // The manifest is the folder's record (written at the start and the end): an output under
      // its name would be lost, or take the record with it.
      if (top == kManifest)
        throw std::invalid_argument("the output " + f + " would be " + what + "'s record, which " + cmd +
                                    " writes itself (" + kManifest + "): give the output another name");
      spec_.outputs.push_back(top);
    }
    // An input inside the folder under a name this run (or the earlier one) writes would be
    // overwritten or removed.
    for (const json& in : spec_.inputs) {
      if (!in.contains("path")) continue;
      const std::string top = top_in_folder(in["path"].get<std::string>());
      if (top.empty()) continue;
      if (top == kManifest || matches(spec_.outputs, top) || matches(old_outputs, top))
        throw std::invalid_argument("the input " + in.value("role", std::string("file")) + " (" +
                                    in["path"].get<std::string>() + ") lies in " + what + " under a name " + cmd +
                                    " writes (" + top + "): move it out of the folder, or use another --out");
    }
    std::vector<std::string> foreign, ours;
    for (const auto& e : fs::directory_iterator(dir_, ec)) {
      const std::string name = e.path().filename().string();
      if (name == kManifest || matches(parents, name)) continue;
      if (name.rfind(kTmpPrefix, 0) == 0) {  // a killed run's half-written file
        fs::remove_all(e.path(), ec);
        continue;
      }
      (matches(old_outputs, name) ? ours : foreign).push_back(name);
    }
    std::sort(foreign.begin(), foreign.end());
    if (!foreign.empty())
      throw std::invalid_argument(what + " holds " + (foreign.size() == 1 ? "a file" : "files") + " " + cmd +
                                  " did not write (" + listed(foreign) + "): use a new or empty folder");
    for (const std::string& p : spec_.outputs)
      if (matches(parents, p.back() == '/' ? p.substr(0, p.size() - 1) : p))
        throw std::invalid_argument(what + ": " + p + " is the parent tool's file (TIGRIS_PARENT_OUTPUTS)");
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
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
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
  const auto text = [](const json& m) { return m.dump(2, ' ', false, json::error_handler_t::replace) + "\n"; };
  write_file(path(kManifest), [&](std::ostream& f) { f << text(manifest_); });
  // What a stop signal leaves: this record, "interrupted" (children.cpp writes it).
  json stopped = manifest_;
  stopped["status"] = "interrupted";
  set_interrupted_record(status == "running" ? fs::absolute(path(kManifest)).string() : "", text(stopped));
}

void write_file(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const fs::path parent = fs::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) fs::create_directories(parent, ec);
  // A device or pipe (/dev/null, /dev/stdout) is written as it is. A file is written beside its
  // path and renamed over it: a failed write leaves the old file whole, and a symbolic link is
  // replaced, never written through (it could point at an input).
  const fs::file_status st = fs::symlink_status(path, ec);
  const bool special = fs::exists(st) && !fs::is_regular_file(st) && !fs::is_symlink(st);
  if (fs::is_directory(st)) throw std::runtime_error(path + ": is a folder, not a file");
  const std::string tmp =
      special
          ? path
          : (parent / (std::string(kTmpPrefix) + fs::path(path).filename().string() + "-" + std::to_string(::getpid())))
                .string();
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
