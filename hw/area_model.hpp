// The area model (docs/model.md): mm2 of a configuration from the area table, by block;
// and the leakage it costs. Every count and size key of the configuration scales its block.
//
// SRAM blocks: each buffer's bytes x area.sram_mm2_per_mib plus area.sram_bank_mm2 per bank.
// Buffers with a banks key use it; the FQQ is one bank; the BQBs, the Node Cache and the
// Leader Buffer are one bank per SU (each SU has its own port into them).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "config.hpp"

namespace tigris::hw {

// The Leader Buffer holds leader.capacity_per_leaf leaders (LeaderBuffer::kLeaderBytes each: the
// point) for each of the 2^tree.top_height leaves, split among the SUs by leaf; a canonical
// tree ("full", about one leaf per point) gets none. The leaders' result lists live in the
// Result Buffer, whose area already counts them.
std::uint64_t leader_buffer_bytes(const AcceleratorConfig& config);
// One RU's copy of the top tree's first fe.top_levels_replicated levels (16-byte nodes).
std::uint64_t replicated_top_bytes(const AcceleratorConfig& config);
// Banks of the SRAMs the SUs share (Node Cache, Leader Buffer): one per SU.
inline int per_su_banks(const AcceleratorConfig& config) { return config.be.search_units; }

struct Area {
  struct Block {
    std::string name;
    double mm2;
  };
  std::vector<Block> sram, logic;  // by buffer; by unit kind

  double sram_mm2() const;
  double logic_mm2() const;
  double total_mm2() const { return sram_mm2() + logic_mm2(); }
  double of(const std::string& block) const;  // one block's mm2 (0 when absent)
  // {"sram", "logic", "total", "by_block": {"sram": {buffer: mm2}, "logic": {unit kind: mm2}}}
  nlohmann::json to_json() const;
};

Area area_of(const AcceleratorConfig& config);

// Static energy of `cycles` cycles: energy.leakage_pj_per_mm2_cycle x total area x cycles.
double leakage_pj(const AcceleratorConfig& config, std::uint64_t cycles);

}  // namespace tigris::hw
