#include "bottleneck.hpp"

#include <algorithm>
#include <cmath>
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
  std::string name, label;                            // "recursion_units", "RUs"
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

// The buffers a unit kind reads and writes, by their stats names.
std::vector<std::string> buffers_of(const std::string& unit) {
  if (unit == "recursion_units") return {"points", "queries", "query_stack", "results"};
  return {"points", "results"};
}

std::string buffer_title(const std::string& name) {
  if (name == "points") return "Point Buffer";
  if (name == "queries") return "Query Buffer";
  if (name == "query_stack") return "Query Stack Buffer";
  if (name == "results") return "Result Buffer";
  return name;
}

// What a Point Buffer bank holds that most walks read: its first top-tree node below the
// levels the RUs keep in registers (heap order, 16-byte entries, words interleaved over the
// banks; tlm/tree_image.hpp), or leaf sets. Empty when the layout is not in the stats.
std::string point_bank_holds(const json& stats, std::uint64_t bank) {
  const json* cfg = stats.contains("config") ? &stats["config"] : nullptr;
  if (!cfg || !stats.contains("tree") || !stats["tree"].contains("top_nodes")) return "";
  const double word = cfg->value("/sram/points/word_bytes"_json_pointer, 16.0);
  const double banks = cfg->value("/sram/points/banks"_json_pointer, 1.0);
  const double replicated = cfg->value("/fe/top_levels_replicated"_json_pointer, 0.0);
  const double top = number(stats["tree"], "top_nodes");
  if (word <= 0 || banks <= 0) return "";
  for (double w = static_cast<double>(bank);; w += banks) {
    const double node = std::floor(w * word / 16.0);
    if (node >= top) return "leaf sets";
    const int level = static_cast<int>(std::floor(std::log2(node + 1.0)));
    if (level < replicated) continue;  // read from the RUs' registers, not this bank
    char b[96];
    if (node == 0)
      std::snprintf(b, sizeof b, "the top tree's root");
    else
      std::snprintf(b, sizeof b, "the top tree's level %d, node %.0f", level, node);
    return b;
  }
}

// The buffer a unit's sram stall waits for (the most conflict cycles among its buffers) and
// its hottest banks: those with at least twice a fair share of the conflict cycles, at most 3.
json sram_hot_spot(const json& stats, const std::string& unit) {
  if (!stats.contains("buffers")) return nullptr;
  const json& buffers = stats["buffers"];
  std::string name;
  double most = 0.0;
  for (const std::string& b : buffers_of(unit))
    if (buffers.contains(b) && number(buffers[b], "conflict_cycles") > most)
      most = number(buffers[b], "conflict_cycles"), name = b;
  if (name.empty() || !buffers[name].contains("banks")) return nullptr;
  const json& per_bank = buffers[name]["banks"]["conflict_cycles"];
  std::vector<std::pair<double, std::uint64_t>> banks;
  for (std::size_t i = 0; i < per_bank.size(); ++i) banks.emplace_back(per_bank[i].get<double>(), i);
  std::stable_sort(banks.begin(), banks.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  json hot = json::array();
  for (const auto& [cycles, bank] : banks) {
    if (hot.size() == 3 || cycles < 2.0 * most / static_cast<double>(banks.size())) break;
    json h = {{"bank", bank}, {"conflict_cycles", cycles}, {"share", cycles / most}};
    if (name == "points") h["holds"] = point_bank_holds(stats, bank);
    hot.push_back(h);
  }
  json j = {{"buffer", name}, {"title", buffer_title(name)}, {"conflict_cycles", most}, {"banks", per_bank.size()}};
  if (!hot.empty()) j["hottest_banks"] = hot;  // none when the waiting spreads evenly
  return j;
}

// "sram stall at the Point Buffer: bank 0 50% of its 6,621,919 conflict cycles (the top tree's
// root), bank 2 5% (level 1, node 2)"; or "... spread over its 64 banks".
std::string describe_hot_spot(const json& h) {
  std::string cycles = std::to_string(static_cast<unsigned long long>(h["conflict_cycles"].get<double>()));
  for (int i = static_cast<int>(cycles.size()) - 3; i > 0; i -= 3) cycles.insert(static_cast<std::size_t>(i), ",");
  char b[160];
  std::string s = "sram stall at the " + h["title"].get<std::string>() + " (" + cycles + " conflict cycles): ";
  if (!h.contains("hottest_banks")) return s + "spread over its " + std::to_string(h["banks"].get<int>()) + " banks";
  bool first = true;
  for (const json& x : h["hottest_banks"]) {
    std::snprintf(b, sizeof b, "%sbank %llu %s", first ? "" : ", ",
                  static_cast<unsigned long long>(x["bank"].get<std::uint64_t>()),
                  percent(x["share"].get<double>()).c_str());
    s += b;
    const std::string holds = x.value("holds", "");
    if (!holds.empty()) s += " (" + holds + ")";
    first = false;
  }
  const json& hottest = h["hottest_banks"][0];
  if (hottest.value("holds", "").rfind("the top tree", 0) == 0)
    s += "; fe.top_levels_replicated keeps the top levels in each RU";
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
  const auto& cause = bound == "result write-back"
                          ? std::make_pair(std::string("result_writeback stall"), writeback(*top))
                          : largest(*top);
  const auto& other_cause = largest(other);
  const double lower = number(stats, "lower_bound_cycles");

  std::string summary = bound == "front-end"  ? "front-end (RU) bound"
                        : bound == "back-end" ? "back-end (SU) bound"
                                              : "result write-back (DRAM) bound";
  summary += ": " + describe(*top) + "; " + describe(other);
  if (units.contains("search_units") && units["search_units"].contains("pe_utilization"))
    summary += "; PE utilization " + percent(number(units["search_units"], "pe_utilization"));
  // An sram stall of a tenth of the bounding kind's time or more names its buffer and banks
  // (and, for the Point Buffer, what they hold).
  double sram_share = 0.0;
  for (const auto& p : top->parts)
    if (p.first == "sram stall") sram_share = p.second;
  const json hot = sram_share >= kSramHotSpot ? sram_hot_spot(stats, top->name) : json();
  if (!hot.is_null()) summary += "; " + describe_hot_spot(hot);
  json j = {{"bound", bound},
            {"unit", top->name},
            {"occupancy", top->occupancy},
            {"cause", cause.first},
            {"share", cause.second},
            {"runner_up",
             {{"unit", other.name},
              {"occupancy", other.occupancy},
              {"cause", other_cause.first},
              {"share", other_cause.second}}}};
  if (lower > 0) {
    j["cycles_over_lower_bound"] = cycles / lower;
    char b[64];
    std::snprintf(b, sizeof b, "; cycles %.1fx the lower bound", cycles / lower);
    summary += b;
  }
  if (!hot.is_null()) j["sram_hot_spot"] = hot;
  j["summary"] = summary;
  return j;
}

}  // namespace tigris
