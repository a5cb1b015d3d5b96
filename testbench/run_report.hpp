// The stats JSON of `tigris run` (docs/stats.md), walked from the accelerator's
// statistics tree: every group's counters where placements() puts them, per-unit detail, sums
// over the units of a kind made by StatGroup::sum, and the derived fields from their formulas
// (stat_formulas.hpp).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hw/top.hpp"
#include "sw_ref/search.hpp"

namespace tigris {

// Where the counters of each statistics group kind appear in the stats JSON: the sum over the
// groups of `kind` merged into the object at `path` ("buffers.{name}": each group at its own
// name instead), and with `per_unit` each group's own counters in id order under `per_unit`.
struct Placement {
  const char* kind;
  const char* path;
  bool per_unit;
};
const std::vector<Placement>& placements();
// The path of `group`'s counters under placement `p`.
std::string placed_at(const Placement& p, const hw::StatGroup& group);

// {"units", "buffers", "energy_pj", "power_w", "area_mm2", "cycles", "seconds"} of a finished
// job of `cycles` cycles: leakage is charged on the configuration's area over those cycles, power
// is the total energy over their time at the clock.
nlohmann::json run_stats_json(const hw::TigrisAccelerator& accel, std::uint64_t cycles);
// The `tigris run` summary lines on energy (total, split, leakage), power and area of a stats
// JSON holding energy_pj, power_w and area_mm2.
std::string energy_area_summary(const nlohmann::json& stats);

}  // namespace tigris
