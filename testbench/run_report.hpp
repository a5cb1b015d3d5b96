// The stats JSON of `tigris run` (docs/stats.md), walked from the accelerator's
// statistics tree: every group's counters as they are, per-unit detail, sums over the units of
// a kind made by StatGroup::sum, and only the ratios computed here.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "hw/top.hpp"
#include "sw_ref/search.hpp"

namespace tigris {

// {"units", "buffers", "energy_pj", "power_w", "area_mm2"} of a finished job of `cycles` cycles:
// leakage is charged on the configuration's area over those cycles, power is the total energy
// over their time at the clock.
nlohmann::json run_stats_json(const hw::TigrisAccelerator& accel, std::uint64_t cycles);
// The `tigris run` summary lines on energy (total, split, leakage), power and area of a stats
// JSON holding energy_pj, power_w and area_mm2.
std::string energy_area_summary(const nlohmann::json& stats);
// max(top visits / #RU, leaf-point visits / (#SU x #PE)): cycles no schedule can beat.
double lower_bound_cycles(const hw::AcceleratorConfig& config, const VisitTotals& visits);

}  // namespace tigris
