// The stats JSON of `tigris run` (DESIGN.md sections 8 and 10), walked from the accelerator's
// statistics tree: every group's counters as they are, per-unit detail, sums over the units of
// a kind made by StatGroup::sum, and only the ratios computed here.
#pragma once

#include <nlohmann/json.hpp>

#include "hw/top.hpp"
#include "sw_ref/search.hpp"

namespace tigris {

// {"units": ..., "buffers": ..., "energy_pj": ...} of a finished job of `cycles` cycles.
nlohmann::json run_stats_json(const hw::TigrisAccelerator& accel, std::uint64_t cycles);
// max(top visits / #RU, leaf-point visits / (#SU x #PE)): cycles no schedule can beat.
double lower_bound_cycles(const hw::AcceleratorConfig& config, const VisitTotals& visits);

}  // namespace tigris
