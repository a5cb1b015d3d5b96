#include "vcd_writer.hpp"

#include <filesystem>
#include <stdexcept>

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

}  // namespace

VcdWriter::VcdWriter(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  out_.open(path);
  if (!out_) throw std::runtime_error(path + ": cannot open for writing");
}

VcdWriter::~VcdWriter() { close(); }

int VcdWriter::add(const std::string& dotted_name, int width) {
  if (header_written_) throw std::logic_error("VCD signals must be declared before changes");
  names_.push_back(dotted_name);
  widths_.push_back(width);
  last_.push_back(0);
  seen_.push_back(false);
  return static_cast<int>(names_.size() - 1);
}

void VcdWriter::write_header() {
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
    if (widths_[i] == 1) out_ << "0" << code(static_cast<int>(i)) << '\n';
    else out_ << "b0 " << code(static_cast<int>(i)) << '\n';
    seen_[i] = true;
  }
  out_ << "$end\n";
  header_written_ = true;
  time_written_ = true;
}

void VcdWriter::change(int id, std::uint64_t time_ps, std::uint64_t value) {
  if (!header_written_) write_header();
  const auto i = static_cast<std::size_t>(id);
  if (seen_[i] && last_[i] == value) return;
  if (time_ps != now_ || !time_written_) {
    if (time_ps < now_) time_ps = now_;  // never go back in time
    out_ << '#' << time_ps << '\n';
    now_ = time_ps;
    time_written_ = true;
  }
  if (widths_[i] == 1) out_ << (value ? '1' : '0') << code(id) << '\n';
  else out_ << 'b' << binary(value, widths_[i]) << ' ' << code(id) << '\n';
  last_[i] = value;
  seen_[i] = true;
}

void VcdWriter::close() {
  if (!out_.is_open()) return;
  if (!header_written_) write_header();
  out_.close();
}

void write_gtkw(const std::string& path, const std::string& vcd_path, const VcdWriter& vcd) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot open for writing");
  f << "[*] GTKWave save file for a Tigris TLM run: open with  gtkwave " << path << "\n";
  f << "[dumpfile] \"" << vcd_path << "\"\n[timestart] 0\n[sst_expanded] 1\n";
  // Zoom to the whole run: GTKWave's zoom z shows 2^-z time units per pixel, about 1000 pixels.
  int zoom = 0;
  while ((std::uint64_t{1} << zoom) * 1000 < vcd.end_time() && zoom < 62) ++zoom;
  f << "*-" << zoom << ".000000 0\n";
  // Group signals by their unit (the name without its last part), in declaration order.
  std::string group;
  for (std::size_t i = 0; i < vcd.names().size(); ++i) {
    const std::string& n = vcd.names()[i];
    const std::string unit = n.substr(0, n.rfind('.'));
    if (unit != group) {
      if (!group.empty()) f << "@1000200\n-" << group << "\n";
      group = unit;
      f << "@800200\n-" << group << "\n";
    }
    f << (vcd.widths()[i] == 1 ? "@28\n" : "@24\n") << n;
    if (vcd.widths()[i] > 1) f << "[" << vcd.widths()[i] - 1 << ":0]";
    f << "\n";
  }
  if (!group.empty()) f << "@1000200\n-" << group << "\n";
}

}  // namespace tigris
