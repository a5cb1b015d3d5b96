// The area table (docs/model.md): 16 nm square millimetres per unit and per SRAM byte and
// bank, configurable as the `area.` keys; hw/area_model.* adds them up over a configuration.
//
// The paper gives totals only: 8.38 mm2 SRAM and 7.19 mm2 logic for 64 RU, 32 SU x 32 PE and
// its buffers. The logic split follows its words ("the datapath area of each RU and each SU's
// PE is mostly dominated by the [float32] euclidean distance"): a PE and an RU are about one
// distance datapath each, the issue logic takes what the total leaves. The SRAM density is
// calibrated so that our default buffers (every one the model has; docs/model.md, "Energy")
// total 8.38 mm2; its 0.096 um2 per bit is a 16 nm high-density bitcell (~0.07 um2) at ~73%
// array efficiency.
#pragma once

#include "config_spec.hpp"

namespace tigris::hw {

struct AreaTable {
  double pe_mm2 = 0.006;
  double ru_mm2 = 0.0075;
  double issue_logic_mm2 = 0.0177;
  double sram_mm2_per_mib = 0.8024;
  double sram_bank_mm2 = 0.002;
  double register_mm2_per_kib = 0.008;

  template <class V>
  void visit(V&& v) {
    const auto mm2 = [&](const char* name, double& field, const char* unit, const char* doc) {
      v(name, field, {unit, in(0, 1e4), doc});  // beyond any chip
    };
    mm2("pe_mm2", pe_mm2, "mm2",
        "one PE: a pipelined float32 squared-distance datapath (3 sub, 3 mul, 2 add); the "
        "paper's logic is dominated by it (1024 PEs: 6.14 of its 7.19 mm2)");
    mm2("ru_mm2", ru_mm2, "mm2",
        "one RU: the same distance datapath (CD) plus the PI compare, query stack pointers and "
        "pipeline control, taken as 1.25 PE");
    mm2("issue_logic_mm2", issue_logic_mm2, "mm2",
        "one SU's issue logic (MQSN associative search, BQB control, Node Set access): what "
        "the paper's 7.19 mm2 leaves after 1024 PEs and 64 RUs, over 32 SUs");
    mm2("sram_mm2_per_mib", sram_mm2_per_mib, "mm2/MiB",
        "SRAM cells and their per-row/column periphery of every buffer: calibrated so the "
        "default configuration's SRAM (our sizes: 2 MiB points, Leader Buffer) is the paper's "
        "8.38 mm2 (16 nm); the paper's 1.5 MB points would give 7.98");
    mm2("sram_bank_mm2", sram_bank_mm2, "mm2/bank",
        "banking overhead: decoder, control and I/O of one SRAM bank (an estimate)");
    mm2("register_mm2_per_kib", register_mm2_per_kib, "mm2/KiB",
        "flip-flop storage (each RU's copy of the top tree's first levels, "
        "fe.top_levels_replicated): ~1 um2 per bit, a 16 nm D flip-flop with its share of "
        "muxing, ~10x the SRAM bit");
  }
};

}  // namespace tigris::hw
