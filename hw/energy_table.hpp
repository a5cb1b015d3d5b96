// The energy table (docs/model.md): picojoules per operation or byte, fed by the energy
// meter as the units work; configurable as the `energy.` keys.
//
// Sources and scaling: operations and SRAM from Horowitz, "Computing's energy problem", ISSCC
// 2014 (45 nm, 0.9 V: fp32 add 0.9 pJ, fp32 mult 3.7 pJ, 8 KB SRAM 64-bit read 10 pJ, 32 KB
// 20 pJ, 1 MB 100 pJ), scaled to 16 nm by kTo16nm: switched energy C V^2 with C following the
// feature size (16/45) and V going from 0.9 V to 0.8 V ((0.8/0.9)^2), 0.281, rounded to 0.28.
// Defaults are rounded to two digits so that they read (and round-trip) as written.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "config_spec.hpp"

namespace tigris::hw {

// 45 nm -> 16 nm for switched energy (see above).
constexpr double kTo16nm = 0.28;

struct EnergyTable {
  double distance_pj = 4.4;      // (3 x 0.9 + 3 x 3.7 + 2 x 0.9) pJ x 0.28 = 4.37
  double ru_node_pj = 4.6;       // distance + one fp32 compare: 16.5 pJ x 0.28 = 4.62
  double leader_check_pj = 4.6;  // distance + compare against thd, as ru_node_pj
  // SRAM per byte at a reference bank size; an access reads or writes one bank, so the price
  // scales with the bank's size (sram_price below): 10 pJ / 8 bytes x 0.28 = 0.35 at 8 KB.
  double sram_ref_pj_per_byte = 0.35;
  std::uint64_t sram_ref_bank_bytes = 8192;
  // Horowitz's 8 KB -> 32 KB doubles the energy for 4x the size (exponent 0.5), 32 KB -> 1 MB
  // gives 5x for 32x (0.46): square-root scaling, as CACTI's wordline and bitline lengths.
  double sram_size_exponent = 0.5;
  double sram_write_factor = 1.0;
  // The SRAM rule at the default Leader Buffer bank, one per SU: 6 KB (hw/area_model.hpp).
  double leader_buffer_pj_per_byte = 0.30;
  double register_pj_per_byte = 0.05;
  double dram_pj_per_byte = 120.0;  // 15 pJ/bit
  // A switch, not a price: the paper's DP4 split gives DRAM 0.2% (docs/model.md, "Two accountings").
  bool charge_result_dram = true;
  double leakage_pj_per_mm2_cycle = 4.0;  // 2 mW/mm2 at 500 MHz

  // pJ per byte of an access to an SRAM of `bytes` in `banks` equal banks: the access drives
  // one bank, priced by the square-root rule from the reference point. Wires between banks
  // (which grow with the whole capacity) are not modelled.
  double sram_price(std::uint64_t bytes, int banks, bool write) const {
    const double bank = static_cast<double>(bytes) / std::max(banks, 1);
    const double read =
        sram_ref_pj_per_byte * std::pow(bank / static_cast<double>(sram_ref_bank_bytes), sram_size_exponent);
    return write ? read * sram_write_factor : read;
  }

  template <class V>
  void visit(V&& v) {
    const auto pj = [&](const char* name, double& field, const char* unit, const char* doc) {
      v(name, field, {unit, in(0, 1e6), doc});  // 1 uJ an operation: beyond any real circuit
    };
    pj("distance_pj", distance_pj, "pJ",
       "PE: one float32 squared distance (3 sub, 3 mul, 2 add); Horowitz ISSCC'14 45 nm fp32 "
       "add 0.9 pJ, mult 3.7 pJ: 15.6 pJ, x0.28 to 16 nm");
    pj("ru_node_pj", ru_node_pj, "pJ",
       "RU: one top-tree node through CD (its squared distance) and PI (one compare): 16.5 pJ at "
       "45 nm (Horowitz), x0.28 to 16 nm");
    pj("leader_check_pj", leader_check_pj, "pJ",
       "Leader Check: one query-to-leader squared distance on a PE and its compare with thd: "
       "16.5 pJ at 45 nm (Horowitz), x0.28 to 16 nm");
    pj("sram_ref_pj_per_byte", sram_ref_pj_per_byte, "pJ/byte",
       "SRAM read of a bank of sram_ref_bank_bytes: Horowitz 8 KB 64-bit read 10 pJ at 45 nm, "
       "x0.28 to 16 nm. A buffer's price: this x (its bytes / banks / sram_ref_bank_bytes) ^ "
       "sram_size_exponent (Point, Query, Query Stack, Result Buffers, Node Cache)");
    v("sram_ref_bank_bytes", sram_ref_bank_bytes,
      {"bytes", in(1, 1e12), "bank size of the sram_ref_pj_per_byte reference point (8 KB)"});
    v("sram_size_exponent", sram_size_exponent,
      {"-", in(0, 2),
       "how SRAM energy per access grows with the bank's size: 0.5 (CACTI-like square root; "
       "Horowitz: 8 KB 10 pJ, 32 KB 20 pJ, 1 MB 100 pJ); 0: one price for every buffer; at most 2 "
       "(energy growing with the square of the bank is already beyond any SRAM, and large exponents "
       "overflow)"});
    pj("sram_write_factor", sram_write_factor, "-",
       "SRAM write / read energy per byte (no published 16 nm split: taken equal)");
    pj("leader_buffer_pj_per_byte", leader_buffer_pj_per_byte, "pJ/byte",
       "Leader Buffer read or write: the SRAM rule at its default bank, one per SU: 1024 leaves x "
       "16 leaders x 12 bytes / 32 SUs = 6 KB, 0.35 x (6/8)^0.5");
    pj("register_pj_per_byte", register_pj_per_byte, "pJ/byte",
       "flip-flop register read (an RU's copy of the top tree's first levels, "
       "fe.top_levels_replicated): ~7x below the smallest SRAM's 0.35 pJ/byte, an estimate "
       "from Horowitz's 64-bit 8 KB SRAM read (10 pJ) vs a register file access (~1 pJ) at 45 nm");
    pj("dram_pj_per_byte", dram_pj_per_byte, "pJ/byte",
       "DRAM access (off chip, not scaled): DDR4 ~15 pJ/bit with I/O, the middle of ~10-20 "
       "pJ/bit from Micron's DDR4 power calculator (TN-40-07); Horowitz 45 nm DDR3: 1.3-2.6 nJ "
       "per 64 bits (20-40 pJ/bit)");
    v("charge_result_dram", charge_result_dram,
      {"-", boolean(),
       "charge dram_pj_per_byte for the result write-back and the leader lists kept in DRAM (true: "
       "the physical machine; false: the paper's accounting, whose DP4 split gives \"DRAM read/write "
       "(0.2%)\", no room for its results' bytes at a DDR4 price; the bytes are still counted)"});
    pj("leakage_pj_per_mm2_cycle", leakage_pj_per_mm2_cycle, "pJ/(mm2 cycle)",
       "static energy per mm2 of area (hw area model) per cycle: an estimate of 2 mW/mm2 for 16 "
       "nm FinFET logic and SRAM at nominal voltage, at 500 MHz (no published figure for this "
       "design)");
  }
};

}  // namespace tigris::hw
