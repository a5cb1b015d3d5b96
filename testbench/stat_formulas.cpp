#include "stat_formulas.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <stdexcept>

#include "config/key_table.hpp"

namespace tigris {

namespace {

using nlohmann::json;

// Recursive descent over  sum := product (('+'|'-') product)*,  product := atom (('*'|'/') atom)*,
// atom := number | path | max '(' sum ',' sum ')' | '(' sum ')'. Left to right, as C++ would
// evaluate the same expression, so a formula gives the bits the old hand-written code gave.
class Parser {
 public:
  Parser(const std::string& text, const json& stats) : s_(text), stats_(stats) {}

  std::optional<double> run() {
    const std::optional<double> v = sum();
    skip();
    if (i_ != s_.size()) fail("unexpected '" + s_.substr(i_, 1) + "'");
    return v;
  }

 private:
  std::optional<double> sum() {
    std::optional<double> v = product();
    for (skip(); i_ < s_.size() && (s_[i_] == '+' || s_[i_] == '-'); skip()) {
      const char op = s_[i_++];
      const std::optional<double> r = product();
      if (v && r)
        v = op == '+' ? *v + *r : *v - *r;
      else
        v.reset();
    }
    return v;
  }

  std::optional<double> product() {
    std::optional<double> v = atom();
    for (skip(); i_ < s_.size() && (s_[i_] == '*' || s_[i_] == '/'); skip()) {
      const char op = s_[i_++];
      const std::optional<double> r = atom();
      if (v && r)
        v = op == '*' ? *v * *r : (*r == 0 ? 0.0 : *v / *r);
      else
        v.reset();
    }
    return v;
  }

  std::optional<double> atom() {
    skip();
    if (i_ >= s_.size()) fail("ends early");
    if (s_[i_] == '(') {
      ++i_;
      const std::optional<double> v = sum();
      expect(')');
      return v;
    }
    if (std::isdigit(static_cast<unsigned char>(s_[i_]))) {
      char* end = nullptr;
      const double v = std::strtod(s_.c_str() + i_, &end);
      i_ = static_cast<std::size_t>(end - s_.c_str());
      return v;
    }
    const std::size_t start = i_;
    while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_' || s_[i_] == '.')) ++i_;
    if (i_ == start) fail("unexpected '" + s_.substr(i_, 1) + "'");
    const std::string name = s_.substr(start, i_ - start);
    if (name == "max") {
      expect('(');
      const std::optional<double> a = sum();
      expect(',');
      const std::optional<double> b = sum();
      expect(')');
      if (!a || !b) return std::nullopt;
      return std::max(*a, *b);
    }
    const json::json_pointer p = config::pointer(name);
    if (!stats_.contains(p)) return std::nullopt;
    const json& v = stats_[p];
    if (!v.is_number()) fail("field " + name + " is not a number");
    return v.get<double>();
  }

  void skip() {
    while (i_ < s_.size() && s_[i_] == ' ') ++i_;
  }
  void expect(char c) {
    skip();
    if (i_ >= s_.size() || s_[i_] != c) fail(std::string("expected '") + c + "'");
    ++i_;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::logic_error("stat formula '" + s_ + "' at " + std::to_string(i_) + ": " + what);
  }

  const std::string& s_;
  const json& stats_;
  std::size_t i_ = 0;
};

}  // namespace

const std::vector<DerivedStat>& derived_stats() {
  static const std::vector<DerivedStat> table = {
      {"seconds", "s", "`cycles` at `clock_mhz`", "cycles / (config.clock_mhz * 1e6)"},
      {"units.recursion_units.utilization", "fraction", "the RUs' share of busy unit-cycles",
       "units.recursion_units.busy_cycles / (units.recursion_units.count * cycles)"},
      {"units.search_units.utilization", "fraction", "the SUs' share of busy unit-cycles",
       "units.search_units.busy_cycles / (units.search_units.count * cycles)"},
      {"units.search_units.pe_utilization", "fraction", "the PEs' share of busy PE-cycles",
       "units.search_units.pe_busy_cycles / (units.search_units.count * units.search_units.pes_per_su * cycles)"},
      {"units.search_units.queries_per_batch", "ratio", "query-leaf visits served per batch",
       "units.search_units.queries / units.search_units.batches"},
      {"power_w", "W", "mean power over the run", "energy_pj.total * 1e-12 / seconds"},
      {"visits.pe_distances", "count",
       "distances the PEs compute: Node Set points, leader-list entries and Leader Check distances",
       "visits.leaf_points + visits.follower_points + visits.leader_checks"},
      {"lower_bound_cycles", "cycles",
       "the ideal machine of this size (docs/model.md, \"Work and the ideal machine\"): every RU one top-tree "
       "node a cycle, every PE one distance a cycle, no bank conflict, free write-back; no schedule beats it",
       "max(visits.top / config.fe.recursion_units, "
       "visits.pe_distances / (config.be.search_units * config.be.pes_per_su))"},
  };
  return table;
}

std::optional<double> evaluate(const std::string& formula, const json& stats) { return Parser(formula, stats).run(); }

void add_derived(json& stats) {
  for (const DerivedStat& d : derived_stats())
    if (const std::optional<double> v = evaluate(d.formula, stats)) stats[config::pointer(d.path)] = *v;
}

}  // namespace tigris
