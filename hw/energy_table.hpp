// The energy table (DESIGN.md section 14): picojoules per operation or byte, fed by the energy
// meter as the units work (16 nm estimates; configurable as the `energy.` keys).
#pragma once

#include "config_spec.hpp"

namespace tigris::hw {

struct EnergyTable {
  double distance_pj = 3.0;
  double ru_node_pj = 3.0;
  double sram_read_pj_per_byte = 0.6;
  double sram_write_pj_per_byte = 0.7;
  double node_cache_pj_per_byte = 0.15;
  double dram_pj_per_byte = 20.0;
  double leader_check_pj = 3.0;
  double leader_buffer_pj_per_byte = 0.1;

  template <class V>
  void visit(V&& v) {
    const auto pj = [&](const char* name, double& field, const char* unit, const char* doc) {
      v(name, field, {unit, at_least(0), doc});
    };
    pj("distance_pj", distance_pj, "pJ", "PE: one float32 squared distance (3 sub, 3 mul, 2 add)");
    pj("ru_node_pj", ru_node_pj, "pJ",
       "RU: one top-tree node through CD (its squared distance) and PI");
    pj("sram_read_pj_per_byte", sram_read_pj_per_byte, "pJ/byte", "global buffer SRAM read");
    pj("sram_write_pj_per_byte", sram_write_pj_per_byte, "pJ/byte", "global buffer SRAM write");
    pj("node_cache_pj_per_byte", node_cache_pj_per_byte, "pJ/byte", "Node Cache access");
    pj("dram_pj_per_byte", dram_pj_per_byte, "pJ/byte", "DRAM access");
    pj("leader_check_pj", leader_check_pj, "pJ",
       "Leader Check: one query-to-leader squared distance on a PE");
    pj("leader_buffer_pj_per_byte", leader_buffer_pj_per_byte, "pJ/byte",
       "Leader Buffer read or write (a small register file per SU)");
  }
};

}  // namespace tigris::hw
