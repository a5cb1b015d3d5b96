#include "schedule_csv.hpp"

#include <charconv>
#include <fstream>
#include <istream>
#include <ostream>
#include <sstream>

#include "sw_ref/io/input_file.hpp"

namespace tigris {

void write_schedule_csv(std::ostream& out, const Schedule& schedule) {
  out << "seq,query,leaf\n";
  std::size_t seq = 0;
  for (const ScheduleEntry& e : schedule) out << seq++ << ',' << e.query << ',' << e.leaf << '\n';
}

namespace {

// Parses "a,b,c" of unsigned integers exactly (no spaces, no signs, no trailing text).
bool parse_row(const std::string& line, std::uint64_t (&v)[3]) {
  const char* p = line.data();
  const char* end = p + line.size();
  if (!line.empty() && line.back() == '\r') --end;
  for (int i = 0; i < 3; ++i) {
    auto [next, ec] = std::from_chars(p, end, v[i]);
    if (ec != std::errc() || next == p) return false;
    p = next;
    if (i < 2) {
      if (p == end || *p != ',') return false;
      ++p;
    }
  }
  return p == end;
}

}  // namespace

Schedule read_schedule_csv(const std::string& path) {
  std::istringstream in(read_input(path, "the schedule file"));
  return read_schedule_csv(in, path);
}

Schedule read_schedule_csv(std::istream& in, const std::string& path) {
  std::string line;
  if (!std::getline(in, line) || (line != "seq,query,leaf" && line != "seq,query,leaf\r"))
    throw InputError(path + ":1: expected the header 'seq,query,leaf'");
  Schedule schedule;
  for (std::size_t lineno = 2; std::getline(in, line); ++lineno) {
    if (line.empty() || line == "\r") continue;
    std::uint64_t v[3];
    const std::string where = path + ":" + std::to_string(lineno) + ": ";
    if (!parse_row(line, v)) throw InputError(where + "expected 'seq,query,leaf' as three unsigned integers, got '" + line + "'");
    if (v[0] != schedule.size())
      throw InputError(where + "seq " + std::to_string(v[0]) + " out of order (expected " +
                       std::to_string(schedule.size()) + ")");
    if (v[1] > 0xFFFFFFFEu || v[2] > 0xFFFFFFFEu) throw InputError(where + "query or leaf out of range");
    schedule.push_back({static_cast<std::uint32_t>(v[1]), static_cast<std::uint32_t>(v[2])});
  }
  return schedule;
}

}  // namespace tigris
