#include "schedule_csv.hpp"

#include <charconv>
#include <fstream>
#include <istream>
#include <ostream>
#include <sstream>

#include "core/input_file.hpp"

namespace tigris {

void write_schedule_csv(std::ostream& out, const Schedule& schedule) {
  out << "seq,query,leaf,event\n";
  std::size_t seq = 0;
  for (const ScheduleEntry& e : schedule)
    out << seq++ << ',' << e.query << ',' << e.leaf << ','
        << (e.event == ScheduleEntry::Event::Finish ? "finish" : "visit") << '\n';
}

namespace {

// Parses "a,b,c" of unsigned integers exactly (no spaces, no signs), then, with `event`,
// ",visit" or ",finish"; nothing after.
bool parse_row(const std::string& line, std::uint64_t (&v)[3], ScheduleEntry::Event* event) {
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
  if (!event) return p == end;
  const std::string rest(p, end);
  if (rest == ",visit")
    *event = ScheduleEntry::Event::Visit;
  else if (rest == ",finish")
    *event = ScheduleEntry::Event::Finish;
  else
    return false;
  return true;
}

}  // namespace

Schedule read_schedule_csv(const std::string& path) {
  std::istringstream in(read_input(path, "the schedule file"));
  return read_schedule_csv(in, path);
}

Schedule read_schedule_csv(std::istream& in, const std::string& path) {
  // The header says the format: "seq,query,leaf,event", or the earlier "seq,query,leaf" (every
  // row a visit).
  std::string line;
  if (std::getline(in, line) && !line.empty() && line.back() == '\r') line.pop_back();
  if (line != "seq,query,leaf,event" && line != "seq,query,leaf")
    throw InputError(path + ":1: expected the header 'seq,query,leaf,event' (or 'seq,query,leaf')");
  const bool events = line == "seq,query,leaf,event";
  Schedule schedule;
  for (std::size_t lineno = 2; std::getline(in, line); ++lineno) {
    if (line.empty() || line == "\r") continue;
    std::uint64_t v[3];
    ScheduleEntry::Event event = ScheduleEntry::Event::Visit;
    const std::string where = path + ":" + std::to_string(lineno) + ": ";
    if (!parse_row(line, v, events ? &event : nullptr))
      throw InputError(where +
                       (events ? "expected 'seq,query,leaf,event': three unsigned integers and visit or finish, got '"
                               : "expected 'seq,query,leaf' as three unsigned integers, got '") +
                       line + "'");
    if (v[0] != schedule.size())
      throw InputError(where + "seq " + std::to_string(v[0]) + " out of order (expected " +
                       std::to_string(schedule.size()) + ")");
    if (v[1] > 0xFFFFFFFEu || v[2] > 0xFFFFFFFEu) throw InputError(where + "query or leaf out of range");
    schedule.push_back({static_cast<std::uint32_t>(v[1]), static_cast<std::uint32_t>(v[2]), event});
  }
  return schedule;
}

}  // namespace tigris
