#include "bottleneck.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>
#include <vector>

namespace tigris {

namespace {

using nlohmann::json;

// An RU's PI/RS dependency stalls (no forwarding) are pipeline cycles, counted in busy_cycles.
constexpr const char* kPartOfBusy = "pi_rs_dependency";

// Stalls that wait on another block: an RU holding a query the BE Query Buffer cannot take is
// back-pressure from the Search Units, and a unit whose results wait for the stream waits on
// DRAM. They are not the unit's own work, so they do not make it the bound.
bool waits_on_another_block(const std::string& cause) { return cause == "bqb_full" || cause == "result_writeback"; }

struct Kind {
  std::string name, label;                          // "recursion_units", "RUs"
  std::vector<std::pair<std::string, double>> parts;  // busy first, then its own stalls by share
  std::vector<std::pair<std::string, double>> waits;  // stalls on another block, by share
  double occupancy = 0.0;                             // busy + own stalls
};

double number(const json& j, const char* key) {
  return j.contains(key) && j[key].is_number() ? j[key].get<double>() : 0.0;
}

Kind kind_of(const json& units, const std::string& name, const std::string& label, double cycles) {
  Kind k{name, label, {}, {}, 0.0};
  if (!units.contains(name)) return k;
  const json& u = units[name];
  const double span = std::max(1.0, number(u, "count")) * cycles;
  k.parts.emplace_back("busy", number(u, "busy_cycles") / span);
  std::vector<std::pair<std::string, double>> stalls;
  if (u.contains("stall_cycles"))
    for (const auto& [cause, v] : u["stall_cycles"].items())
      if (cause != kPartOfBusy && v.is_number() && v.get<double>() > 0)
        (waits_on_another_block(cause) ? k.waits : stalls).emplace_back(cause + " stall", v.get<double>() / span);
  const auto by_share = [](const auto& a, const auto& b) { return a.second > b.second; };
  std::stable_sort(stalls.begin(), stalls.end(), by_share);
  std::stable_sort(k.waits.begin(), k.waits.end(), by_share);
  k.parts.insert(k.parts.end(), stalls.begin(), stalls.end());
  for (const auto& p : k.parts) k.occupancy += p.second;
  return k;
}

const std::pair<std::string, double>& largest(const Kind& k) {
  return *std::max_element(k.parts.begin(), k.parts.end(),
                           [](const auto& a, const auto& b) { return a.second < b.second; });
}

std::string percent(double f) {
  char b[32];
  std::snprintf(b, sizeof b, "%.0f%%", 100 * f);
  return b;
}

// "RUs 94% occupied: sram stall 49%, busy 45%; waiting on other blocks 1%: bqb_full stall 1%";
// parts under 0.5% left out.
std::string describe(const Kind& k) {
  std::vector<std::pair<std::string, double>> parts = k.parts;
  std::stable_sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  std::string s = k.label + " " + percent(k.occupancy) + " occupied:";
  bool first = true;
  for (const auto& [name, share] : parts)
    if (share >= 0.005 || name == "busy") {
      s += (first ? " " : ", ") + name + " " + percent(share);
      first = false;
    }
  double waiting = 0.0;
  std::string list;
  for (const auto& [name, share] : k.waits)
    if (share >= 0.005) waiting += share, list += (list.empty() ? "" : ", ") + name + " " + percent(share);
  if (!list.empty()) s += "; waiting on other blocks " + percent(waiting) + ": " + list;
  return s;
}

}  // namespace

json bottleneck_json(const json& stats) {
  const double cycles = number(stats, "cycles");
  if (cycles <= 0 || !stats.contains("units")) return {{"bound", "none"}, {"summary", "no cycles"}};
  const json& units = stats["units"];
  const Kind ru = kind_of(units, "recursion_units", "RUs", cycles);
  const Kind su = kind_of(units, "search_units", "SUs", cycles);

  const auto writeback = [](const Kind& k) {
    for (const auto& p : k.waits)
      if (p.first == "result_writeback stall") return p.second;
    return 0.0;
  };
  std::string bound;
  const Kind* top = nullptr;
  if (std::max(writeback(ru), writeback(su)) > kWritebackBound) {
    bound = "result write-back";
    top = writeback(ru) >= writeback(su) ? &ru : &su;
  } else {
    top = ru.occupancy >= su.occupancy ? &ru : &su;
    bound = top == &ru ? "front-end" : "back-end";
  }
  const Kind& other = top == &ru ? su : ru;
  const auto& cause = bound == "result write-back" ? std::make_pair(std::string("result_writeback stall"), writeback(*top))
                                                    : largest(*top);
  const auto& other_cause = largest(other);
  const double lower = number(stats, "lower_bound_cycles");

  std::string summary = bound == "front-end" ? "front-end (RU) bound"
                        : bound == "back-end" ? "back-end (SU) bound"
                                              : "result write-back (DRAM) bound";
  summary += ": " + describe(*top) + "; " + describe(other);
  if (units.contains("search_units") && units["search_units"].contains("pe_utilization"))
    summary += "; PE utilization " + percent(number(units["search_units"], "pe_utilization"));
  json j = {{"bound", bound},
            {"unit", top->name},
            {"occupancy", top->occupancy},
            {"cause", cause.first},
            {"share", cause.second},
            {"runner_up",
             {{"unit", other.name}, {"occupancy", other.occupancy}, {"cause", other_cause.first},
              {"share", other_cause.second}}}};
  if (lower > 0) {
    j["cycles_over_lower_bound"] = cycles / lower;
    char b[64];
    std::snprintf(b, sizeof b, "; cycles %.1fx the lower bound", cycles / lower);
    summary += b;
  }
  j["summary"] = summary;
  return j;
}

}  // namespace tigris
