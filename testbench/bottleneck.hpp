// What bounds a run: the `bottleneck` object of stats.json and the summary's "bound" line,
// computed from the statistics alone (so the report and `tigris diff` reuse it, never redo it).
//
// Each unit kind (Recursion Units, Search Units) spends its unit-cycles (count x cycles) busy,
// stalled by a named cause, or idle (an RU's pi_rs_dependency stalls are part of its busy
// cycles, not added again). Two stalls wait on another block: an RU's bqb_full (back-pressure
// from the Search Units) and result_writeback (DRAM). The kind occupied the larger share by its
// own work (busy + its other stalls) bounds the run: front-end (RU) or back-end (SU) bound,
// unless a kind waits on the result write-back for more than kWritebackBound of its cycles: then
// the run is write-back bound. The cause is the largest part of the bounding kind's own work; the
// runner-up is the other kind.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace tigris {

inline constexpr double kWritebackBound = 0.3;
// An sram stall of at least this share of the bounding kind's cycles names its buffer's hottest
// banks (`sram_hot_spot`, and the summary).
inline constexpr double kSramHotSpot = 0.1;

// From a stats JSON holding cycles, lower_bound_cycles and units.{recursion_units,search_units}
// (count, busy_cycles, stall_cycles.*; search_units.pe_utilization): {bound, unit, occupancy,
// cause, share, runner_up {unit, occupancy, cause, share}, cycles_over_lower_bound,
// sram_hot_spot {buffer, title, conflict_cycles, banks, hottest_banks[] {bank, conflict_cycles,
// share, holds}}, summary}; buffers.<name>.banks and tree.top_nodes feed sram_hot_spot.
// A run of 0 cycles gives {bound: "none", summary: "no cycles"}.
nlohmann::json bottleneck_json(const nlohmann::json& stats);

}  // namespace tigris
