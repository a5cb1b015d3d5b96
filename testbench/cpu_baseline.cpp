#include "cpu_baseline.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "core/build_info.hpp"

namespace tigris {

using nlohmann::ordered_json;

Spread spread_of(const std::vector<double>& samples) {
  if (samples.empty()) throw std::invalid_argument("a timing spread needs at least one sample");
  for (double x : samples)
    if (!std::isfinite(x)) throw std::invalid_argument("a timing sample is not a finite number");
  std::vector<double> v = samples;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  Spread s;
  s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  s.min = v.front();
  s.max = v.back();
  s.samples = samples;
  return s;
}

ordered_json to_json(const Spread& s) {
  return {{"median", s.median}, {"min", s.min}, {"max", s.max}, {"samples", s.samples}};
}

namespace {
// A ratio without a figure (null) when a denominator is not positive.
ordered_json ratio(double a, double b) {
  return b > 0.0 && std::isfinite(a / b) ? ordered_json(a / b) : ordered_json();
}
}  // namespace

ordered_json ratio_range(const Spread& base, const Spread& x) {
  return {{"median", ratio(base.median, x.median)}, {"min", ratio(base.min, x.max)}, {"max", ratio(base.max, x.min)}};
}

ordered_json reduction_range_percent(const Spread& base, const Spread& x) {
  const auto red = [](double b, double v) { return b > 0.0 ? ordered_json(100.0 * (1.0 - v / b)) : ordered_json(); };
  return {{"median", red(base.median, x.median)}, {"min", red(base.min, x.max)}, {"max", red(base.max, x.min)}};
}

std::string spread_cell(const Spread& s, const char* fmt) {
  char a[32], b[32], c[32];
  std::snprintf(a, sizeof a, fmt, s.median);
  if (s.samples.size() < 2) return a;
  std::snprintf(b, sizeof b, fmt, s.min);
  std::snprintf(c, sizeof c, fmt, s.max);
  return std::string(a) + " [" + b + "-" + c + "]";
}

std::string range_cell(const ordered_json& range, const char* fmt) {
  const auto num = [&](const char* k) -> std::string {
    if (!range.contains(k) || !range[k].is_number()) return "-";
    char b[32];
    std::snprintf(b, sizeof b, fmt, range[k].get<double>());
    return b;
  };
  const std::string med = num("median"), lo = num("min"), hi = num("max");
  return lo == hi ? med : med + " [" + lo + ", " + hi + "]";
}

namespace {

std::array<double, 3> load_average() {
  std::array<double, 3> l{NAN, NAN, NAN};
  std::ifstream f("/proc/loadavg");
  f >> l[0] >> l[1] >> l[2];
  if (!f) l = {NAN, NAN, NAN};
  return l;
}

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(" \t", colon + 1));
    }
  return "unknown";
}

ordered_json loads(const std::array<double, 3>& l) {
  ordered_json j;
  for (const auto& [name, x] : {std::pair<const char*, double>{"1min", l[0]}, {"5min", l[1]}, {"15min", l[2]}})
    j[name] = std::isfinite(x) ? ordered_json(x) : ordered_json();
  return j;
}

}  // namespace

Machine machine_before() {
  Machine m;
  m.cpu_model = cpu_model();
  char host[256] = "";
  if (::gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
  m.host = host[0] ? host : "unknown";
  m.commit = build_commit();
  m.cores = std::max(1u, std::thread::hardware_concurrency());
  m.load_before = load_average();
  return m;
}

void machine_after(Machine& m) { m.load_after = load_average(); }

ordered_json to_json(const Machine& m) {
  return {{"cpu_model", m.cpu_model},
          {"cores", m.cores},
          {"host", m.host},
          {"commit", m.commit},
          {"load_average_before", loads(m.load_before)},
          {"load_average_after", loads(m.load_after)}};
}

std::string machine_line(const Machine& m) {
  char b[512];
  std::snprintf(b, sizeof b, "%s, %u cores, load %.2f before and %.2f after (1 min), commit %s", m.cpu_model.c_str(),
                m.cores, m.load_before[0], m.load_after[0], m.commit.c_str());
  return b;
}

std::vector<std::string> baseline_warnings(const Machine& m, const std::vector<std::pair<std::string, Spread>>& timed) {
  std::vector<std::string> w;
  // Our own runs count in the load after them, so only the load before says the machine was busy.
  if (std::isfinite(m.load_before[0]) && m.load_before[0] >= 0.5 * m.cores) {
    char b[200];
    std::snprintf(b, sizeof b,
                  "the machine was busy before the runs (1-minute load %.2f on %u cores): the CPU "
                  "timings include other work",
                  m.load_before[0], m.cores);
    w.push_back(b);
  }
  for (const auto& [name, s] : timed) {
    if (s.samples.size() < 2) {
      w.push_back(name + " was timed once: no spread (use --repeat 3 or more for a figure to quote)");
    } else if (s.max - s.min > 0.25 * s.median) {
      char b[200];
      std::snprintf(b, sizeof b,
                    " varied by %.0f%% of its median between runs: the machine may have been busy; "
                    "rerun on an idle machine or with a larger --repeat",
                    100.0 * (s.max - s.min) / s.median);
      w.push_back(name + b);
    }
  }
  return w;
}

}  // namespace tigris
