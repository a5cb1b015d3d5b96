// CPU baselines a user can quote: a CPU back-end timed several times gives a median
// with its min and max, a speed-up against it a range, and the machine that measured it (CPU,
// cores, load before and after, commit) travels with the numbers. `register --compare` and
// `odometry --compare` use it; docs/performance.md says how to get a quotable baseline.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace tigris {

struct Spread {
  double median = 0.0, min = 0.0, max = 0.0;
  std::vector<double> samples;  // in the order measured
};
// Throws std::invalid_argument on no samples or a non-finite one.
Spread spread_of(const std::vector<double>& samples);
// A modeled (deterministic) figure: one sample.
inline Spread exact_value(double x) { return spread_of({x}); }
nlohmann::ordered_json to_json(const Spread& s);  // {"median","min","max","samples"}

// base / x, the median's ratio and the widest range the samples allow:
// {"median": base.median / x.median, "min": base.min / x.max, "max": base.max / x.min}.
nlohmann::ordered_json ratio_range(const Spread& base, const Spread& x);
// The reduction 1 - x / base in percent, as a range.
nlohmann::ordered_json reduction_range_percent(const Spread& base, const Spread& x);

// "7.91 [6.70-9.70]" (a single sample: "7.91"), each number printed with `fmt`.
std::string spread_cell(const Spread& s, const char* fmt);
std::string range_cell(const nlohmann::ordered_json& range, const char* fmt);

struct Machine {
  std::string cpu_model, host, commit;
  unsigned cores = 0;
  std::array<double, 3> load_before{}, load_after{};  // /proc/loadavg: 1, 5, 15 minutes
};
Machine machine_before();        // everything but load_after
void machine_after(Machine& m);  // load_after, when the timed runs are over
nlohmann::ordered_json to_json(const Machine& m);
std::string machine_line(const Machine& m);  // one line for the table's footer

// Why the CPU timings may not be quotable, empty when nothing says so: a machine that was
// already busy (1-minute load before the runs at least half the cores), a single timing, or
// samples spread by more than 25% of their median.
std::vector<std::string> baseline_warnings(const Machine& m, const std::vector<std::pair<std::string, Spread>>& timed);

}  // namespace tigris
