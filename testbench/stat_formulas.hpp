// Derived statistics, each a formula over other fields of the stats JSON declared once in
// stat_formulas.cpp: the run computes the field from the formula's text (evaluate), and the
// schema (`tigris run --stats-schema`, docs/stats.md) prints the same text.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tigris {

struct DerivedStat {
  std::string path;  // where the value goes: "units.search_units.utilization"
  std::string unit;  // "fraction", "ratio", "s", "W", "cycles"
  std::string meaning;
  std::string formula;  // over dotted paths of the stats JSON: + - * / ( ) max(a, b) and numbers
};

// In evaluation order: a formula may use the fields of the ones before it.
const std::vector<DerivedStat>& derived_stats();

// The value of `formula` over `stats`; nullopt when a field it names is absent (a job's stats
// hold no visits, so they get no lower bound). A division by zero gives 0: an idle unit has no
// utilization. A malformed formula or a field that is not a number is a std::logic_error.
std::optional<double> evaluate(const std::string& formula, const nlohmann::json& stats);

// Sets every derived field whose inputs `stats` holds, in table order.
void add_derived(nlohmann::json& stats);

}  // namespace tigris
