#include "vcd_writer.hpp"

#include <unistd.h>

#include <exception>
#include <filesystem>
#include <stdexcept>

#include "core/out_folder.hpp"

namespace tigris {

namespace {

// VCD identifiers: printable characters '!'..'~', base 94.
std::string code(int id) {
  std::string s;
  do {
    s += static_cast<char>('!' + id % 94);
    id /= 94;
  } while (id > 0);
  return s;
}

std::string binary(std::uint64_t v, int width) {
  std::string s;
  for (int b = width - 1; b >= 0; --b) s += ((v >> b) & 1) ? '1' : '0';
  const auto first = s.find('1');
  return first == std::string::npos ? "0" : s.substr(first);
}

// The file written in place of `path` until it is whole (the core's convention, as
// core/out_folder.hpp's write_file): a killed run leaves no half file under the name and
// never writes through a symbolic link; a device (/dev/null) is written directly.
std::string temp_beside(const std::string& path) { return temp_path_for(path); }

// Renames a finished temporary over its path.
void commit(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  if (tmp != path) std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error(path + ": cannot write: " + ec.message());
}

}  // namespace

VcdWriter::VcdWriter(const std::string& path) : path_(path), tmp_(temp_beside(path)) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  if (std::filesystem::is_directory(path, ec)) throw std::runtime_error(path + ": is a folder, not a file");
  out_.open(tmp_);
  if (!out_) throw std::runtime_error(path + ": cannot open for writing");
}

VcdWriter::~VcdWriter() {
  try {
    close();
  } catch (const std::exception&) {  // a destructor must not throw; close() first to see errors
    std::error_code ec;
    if (tmp_ != path_) std::filesystem::remove(tmp_, ec);
  }
}

int VcdWriter::add(const std::string& dotted_name, int width) {
  if (header_written_) throw std::logic_error("VCD signals must be declared before changes");
  names_.push_back(dotted_name);
  widths_.push_back(width);
  last_.push_back(0);
  seen_.push_back(false);
  return static_cast<int>(names_.size() - 1);
}

void VcdWriter::write_header() {
  if (!comment_.empty()) {
    out_ << "$comment\n";
    for (const std::string& line : comment_) {
      std::string safe = line;  // "$end" inside would close the comment early
      for (std::size_t at; (at = safe.find("$end")) != std::string::npos;) safe.replace(at, 4, "$ end");
      out_ << "  " << safe << "\n";
    }
    out_ << "$end\n";
  }
  out_ << "$timescale 1ps $end\n";
  // Nested scopes from the dotted names (declared in order, so a scope's signals are adjacent).
  std::vector<std::string> open;
  for (std::size_t i = 0; i < names_.size(); ++i) {
    std::vector<std::string> parts;
    std::size_t from = 0;
    for (std::size_t dot; (dot = names_[i].find('.', from)) != std::string::npos; from = dot + 1)
      parts.push_back(names_[i].substr(from, dot - from));
    const std::string leaf = names_[i].substr(from);
    std::size_t common = 0;
    while (common < open.size() && common < parts.size() && open[common] == parts[common]) ++common;
    for (std::size_t k = open.size(); k > common; --k) out_ << "$upscope $end\n";
    open.resize(common);
    for (std::size_t k = common; k < parts.size(); ++k) {
      out_ << "$scope module " << parts[k] << " $end\n";
      open.push_back(parts[k]);
    }
    out_ << "$var wire " << widths_[i] << ' ' << code(static_cast<int>(i)) << ' ' << leaf;
    if (widths_[i] > 1) out_ << " [" << widths_[i] - 1 << ":0]";
    out_ << " $end\n";
  }
  for (std::size_t k = 0; k < open.size(); ++k) out_ << "$upscope $end\n";
  out_ << "$enddefinitions $end\n#0\n$dumpvars\n";
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (widths_[i] == 1)
      out_ << "0" << code(static_cast<int>(i)) << '\n';
    else
      out_ << "b0 " << code(static_cast<int>(i)) << '\n';
    seen_[i] = true;
  }
  out_ << "$end\n";
  header_written_ = true;
  time_written_ = true;
}

void VcdWriter::change_at(int id, std::uint64_t time_ps, std::uint64_t value, std::uint64_t now_ps) {
  if (booked_.empty() && time_ps <= now_ps) return emit(id, time_ps, value);
  booked_.push({time_ps, seq_++, id, static_cast<std::int64_t>(value), false});
  flush(now_ps);
}

void VcdWriter::add_at(int id, std::uint64_t time_ps, std::int64_t delta, std::uint64_t now_ps) {
  booked_.push({time_ps, seq_++, id, delta, true});
  flush(now_ps);
}

void VcdWriter::flush(std::uint64_t until_ps) {
  while (!booked_.empty() && booked_.top().time <= until_ps) {
    const Booked b = booked_.top();
    booked_.pop();
    const auto i = static_cast<std::size_t>(b.id);
    emit(b.id, b.time,
         b.delta ? static_cast<std::uint64_t>(static_cast<std::int64_t>(last_[i]) + b.value)
                 : static_cast<std::uint64_t>(b.value));
  }
}

void VcdWriter::emit(int id, std::uint64_t time_ps, std::uint64_t value) {
  if (!header_written_) write_header();
  const auto i = static_cast<std::size_t>(id);
  if (seen_[i] && last_[i] == value) return;
  if (time_ps != now_ || !time_written_) {
    if (time_ps < now_) time_ps = now_;  // never go back in time
    out_ << '#' << time_ps << '\n';
    now_ = time_ps;
    time_written_ = true;
  }
  if (widths_[i] == 1)
    out_ << (value ? '1' : '0') << code(id) << '\n';
  else
    out_ << 'b' << binary(value, widths_[i]) << ' ' << code(id) << '\n';
  last_[i] = value;
  seen_[i] = true;
}

void VcdWriter::close() {
  if (!out_.is_open()) return;
  flush(~std::uint64_t{0});
  if (!header_written_) write_header();
  out_.flush();
  const bool ok = out_.good();
  out_.close();
  if (!ok || out_.fail()) throw std::runtime_error(path_ + ": writing the waveforms failed (disk full?)");
  commit(tmp_, path_);
}

void write_gtkw(const std::string& path, const std::string& vcd_path, const VcdWriter& vcd, std::uint64_t start_ps,
                const std::vector<std::string>& comment) {
  const std::string tmp = temp_beside(path);
  std::ofstream f(tmp);
  if (!f) throw std::runtime_error(path + ": cannot open for writing");
  struct Check {  // the save file is complete, renamed over its path, or an error names it
    std::ofstream& f;
    const std::string& tmp;
    const std::string& path;
    ~Check() noexcept(false) {
      f.flush();
      const bool ok = static_cast<bool>(f);
      f.close();
      std::error_code ec;
      if (ok && std::uncaught_exceptions() == 0) {
        commit(tmp, path);
      } else {
        if (tmp != path) std::filesystem::remove(tmp, ec);
        if (std::uncaught_exceptions() == 0) throw std::runtime_error(path + ": write failed");
      }
    }
  } check{f, tmp, path};
  f << "[*] GTKWave save file for a Tigris TLM run: open with  gtkwave " << path << "\n";
  for (const std::string& line : comment) f << "[*] " << line << "\n";
  std::error_code ec;
  const std::filesystem::path dump = std::filesystem::absolute(vcd_path, ec);
  f << "[dumpfile] \"" << (ec ? vcd_path : dump.lexically_normal().string()) << "\"\n[timestart] " << start_ps
    << "\n[size] 1200 800\n[sst_expanded] 1\n";
  // Wide enough for "tigris.all.writeback_backlog_bytes[31:0]=1234567" beside the waves.
  f << "[signals_width] 420\n[sst_width] 220\n";
  // Zoom to the job's span. Measured with GTKWave 3.3.118 (Debian 12) under Xvfb: zoom -z
  // shows about 2^z x 3.2 time units across the wave pane of this window size, so the
  // smallest z with 2^z x 3 >= span shows the whole job (1.07 to 2.1 times its span).
  const std::uint64_t span = vcd.end_time() > start_ps ? vcd.end_time() - start_ps : 1;
  int zoom = 0;
  while ((std::uint64_t{1} << zoom) * 3 < span && zoom < 62) ++zoom;
  f << "*-" << zoom << ".000000 " << start_ps << "\n";  // the primary marker at START
  // Groups by unit (the name without its last part), in declaration order: open for the
  // first, collapsed (GTKWave's closed-group flags) for the rest.
  std::string group;
  bool first = true;
  const auto close = [&] {
    if (!group.empty()) f << (first ? "@1000200\n-" : "@1401200\n-") << group << "\n";
  };
  for (std::size_t i = 0; i < vcd.names().size(); ++i) {
    const std::string& n = vcd.names()[i];
    const std::string unit = n.substr(0, n.rfind('.'));
    if (unit != group) {
      close();
      if (!group.empty()) first = false;
      group = unit;
      f << (first ? "@800200\n-" : "@c00200\n-") << group << "\n";
    }
    // The aggregates as step plots (analog step | decimal | right-justified, then two rows
    // of analog stretch for height); unit signals as bits or decimal numbers.
    f << (first && vcd.widths()[i] > 1 ? "@8024\n" : vcd.widths()[i] == 1 ? "@28\n" : "@24\n") << n;
    if (vcd.widths()[i] > 1) f << "[" << vcd.widths()[i] - 1 << ":0]";
    f << "\n";
    if (first && vcd.widths()[i] > 1) f << "@20000\n-\n@20000\n-\n";
  }
  close();
}

}  // namespace tigris
