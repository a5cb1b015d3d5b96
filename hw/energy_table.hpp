// The energy table (DESIGN.md section 14): picojoules per operation or byte, fed by the energy
// meter as the units work (16 nm estimates; configurable).
#pragma once

namespace tigris::hw {

struct EnergyTable {
  double distance_pj = 3.0;     // PE: one float32 dist2 (3 sub, 3 mul, 2 add)
  double ru_node_pj = 3.0;      // RU: one top-tree node through CD (its dist2) and PI
  double sram_read_pj_per_byte = 0.6;
  double sram_write_pj_per_byte = 0.7;
  double node_cache_pj_per_byte = 0.15;
  double dram_pj_per_byte = 20.0;
};

}  // namespace tigris::hw
