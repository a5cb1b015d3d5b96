// Fuzz target: the schedule CSV reader (traces/schedule_csv.hpp, `--schedule`). The reader must
// give a clean error naming the file, or a schedule whose entries are the file's rows (checked
// by an independent split of each non-empty line) and that survives a write and re-read.
#include <sstream>
#include <string>

#include "fuzz_common.hpp"
#include "traces/schedule_csv.hpp"

namespace {

using namespace tigris_fuzz;
const char* const kTarget = "schedule_csv";
const std::string kLabel = "fuzz.csv";

}  // namespace

extern "C" int TIGRIS_FUZZ_ENTRY(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  tigris::Schedule schedule;
  try {
    std::istringstream in(text);
    schedule = tigris::read_schedule_csv(in, kLabel);
  } catch (const tigris::InputError& e) {
    if (!names_source(e.what(), kLabel)) wrong_read(kTarget, std::string("error without the file name: ") + e.what());
    return 0;
  }
  // Independent decode: every line after the first that is not empty is "seq,query,leaf" and,
  // when the header has it, ",event".
  std::istringstream lines(text);
  std::string line;
  std::getline(lines, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  const bool events = line == "seq,query,leaf,event";
  std::size_t row = 0;
  while (std::getline(lines, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::size_t c1 = line.find(','), c2 = line.find(',', c1 + 1);
    if (row >= schedule.size() || c1 == std::string::npos || c2 == std::string::npos)
      wrong_read(kTarget, "row " + std::to_string(row) + " not in the schedule: " + line);
    const std::size_t c3 = events ? line.find(',', c2 + 1) : std::string::npos;
    if (events && c3 == std::string::npos) wrong_read(kTarget, "row " + std::to_string(row) + " has no event: " + line);
    const unsigned long long seq = std::stoull(line.substr(0, c1)),
                             query = std::stoull(line.substr(c1 + 1, c2 - c1 - 1)),
                             leaf = std::stoull(line.substr(c2 + 1, c3 == std::string::npos ? c3 : c3 - c2 - 1));
    const bool finish = events && line.substr(c3 + 1) == "finish";
    if (seq != row || query != schedule[row].query || leaf != schedule[row].leaf ||
        finish != (schedule[row].event == tigris::ScheduleEntry::Event::Finish))
      wrong_read(kTarget, "row " + std::to_string(row) + " read differently: " + line);
    ++row;
  }
  if (row != schedule.size())
    wrong_read(kTarget, std::to_string(schedule.size()) + " entries read from " + std::to_string(row) + " rows");
  std::ostringstream out;
  tigris::write_schedule_csv(out, schedule);
  std::istringstream again(out.str());
  if (!(tigris::read_schedule_csv(again, kLabel) == schedule)) wrong_read(kTarget, "write and re-read differ");
  return 0;
}
