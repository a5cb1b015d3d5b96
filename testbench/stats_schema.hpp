// The schema of `tigris run`'s stats.json: every field's path, unit and meaning, walked from
// where each is declared: the counters at their fields (hw/stats.hpp) placed by
// run_report.cpp's placements(), the derived fields with their formulas (stat_formulas.hpp),
// the configuration keys at theirs (hw/config.hpp), and the run's other fields in the table of
// stats_schema.cpp. `tigris run --stats-schema` prints it; docs/stats.md's tables are generated
// from it (scripts/stats_doc.py) and a test holds both to it and to real runs.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tigris {

struct StatField {
  std::string section;  // the docs section: run, visits, units, buffers, energy, latency, ...
  std::string path;     // dotted; `[]` marks an array's elements, `*` one name of a listed set
  std::string unit;     // cycles, bytes, count, fraction, ratio, s, m, pJ, W, mm2, text, bool, ...
  std::string meaning;
  std::string formula;  // derived fields only
};

// Every field, by section in the docs' order, then by block (units and buffers) and origin.
std::vector<StatField> stats_schema();
// {"sections": [{"id", "title"}], "fields": [{"section", "path", "unit", "meaning"[, "formula"]}]}
nlohmann::json stats_schema_json();

}  // namespace tigris
