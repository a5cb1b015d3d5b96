// A small Value Change Dump writer for waveforms (GTKWave). Signals are declared up front in
// dotted scopes ("tigris.fe.ru0.busy"). Units record changes when they happen, or when they
// book them ahead (a walk that will stall on SRAM after its pipeline cycles), so tracing adds
// no process and no event to the simulation: changes booked for later wait in a queue and are
// written in time order once the simulation has reached their time.
#pragma once

#include <cstdint>
#include <fstream>
#include <functional>
#include <queue>
#include <string>
#include <vector>

namespace tigris {

class VcdWriter {
 public:
  // Opens `path`; throws std::runtime_error if it cannot be written.
  explicit VcdWriter(const std::string& path);
  ~VcdWriter();

  // Lines for the header's $comment (what made the dump: command line, inputs, configuration
  // digest, commit); before the first change.
  void set_comment(std::vector<std::string> lines) { comment_ = std::move(lines); }
  // Declares a signal (before the first change); returns its handle.
  int add(const std::string& dotted_name, int width);
  // Records that signal `id` has `value` from `time_ps` (the current time) on; repeated values
  // are dropped.
  void change(int id, std::uint64_t time_ps, std::uint64_t value) { change_at(id, time_ps, value, time_ps); }
  // The same for a change at `time_ps` >= `now_ps`, the current time. A signal's own changes
  // must be booked in time order.
  void change_at(int id, std::uint64_t time_ps, std::uint64_t value, std::uint64_t now_ps);
  // Adds `delta` to signal `id` from `time_ps` (>= now_ps) on: a sum over units, whose
  // bookings come in any order.
  void add_at(int id, std::uint64_t time_ps, std::int64_t delta, std::uint64_t now_ps);
  // Writes what is left; throws std::runtime_error naming the file if anything failed.
  void close();

  const std::vector<std::string>& names() const { return names_; }
  const std::vector<int>& widths() const { return widths_; }
  std::uint64_t end_time() const { return now_; }

 private:
  void write_header();
  void emit(int id, std::uint64_t time_ps, std::uint64_t value);
  void flush(std::uint64_t until_ps);  // writes the booked changes up to that time
  struct Booked {
    std::uint64_t time, seq;
    int id;
    std::int64_t value;
    bool delta;
    bool operator>(const Booked& o) const { return time != o.time ? time > o.time : seq > o.seq; }
  };
  std::priority_queue<Booked, std::vector<Booked>, std::greater<Booked>> booked_;
  std::uint64_t seq_ = 0;
  std::string path_, tmp_;  // written into tmp_ beside path_, renamed over it by close()
  std::ofstream out_;
  std::vector<std::string> names_, comment_;
  std::vector<int> widths_;
  std::vector<std::uint64_t> last_;
  std::vector<bool> seen_;
  bool header_written_ = false;
  std::uint64_t now_ = 0;
  bool time_written_ = false;
};

// A GTKWave save file that opens `vcd_path` on the span from `start_ps` (the job's START, also
// the marker) to the last change, with every declared signal grouped by unit: the first group
// (the aggregate traces) open, the per-unit groups collapsed below it. The dump is named by its
// absolute path, so the save file opens it from any working folder; `comment` lines (what made
// the run) go into its header.
void write_gtkw(const std::string& path, const std::string& vcd_path, const VcdWriter& vcd, std::uint64_t start_ps = 0,
                const std::vector<std::string>& comment = {});

}  // namespace tigris
