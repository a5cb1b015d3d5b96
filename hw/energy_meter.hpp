// The energy meter (docs/model.md): units feed it operation and byte counts as they
// happen, each on a line priced from the energy table (hw/energy_table.hpp); energy is count x
// price per line, summed by component. Counting rather than adding picojoules keeps the totals
// exact and independent of the order events happen in.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "energy_table.hpp"
#include "stats.hpp"

namespace tigris::hw {

class EnergyMeter {
 public:
  // The components of `energy_pj` in the stats.
  enum class Component { Pe, Ru, SramRead, SramWrite, NodeCache, LeaderBuffer, Dram };

  explicit EnergyMeter(const EnergyTable& table) : table_(table), stats_("energy") {}

  const EnergyTable& table() const { return table_; }
  StatGroup& stats() { return stats_; }
  // The line `name` of `component` at `pj` per count (created by its first user, shared by the
  // rest: every PE feeds "pe.distance"); its counter is in the meter's stats group.
  Counter& line(const std::string& name, Component component, double pj);
  // Picojoules: {pe, ru, sram_read, sram_write, node_cache, leader_buffer, dram, leakage,
  // total} and `by_unit`, the same total by the unit kind that spent it (unit_of below).
  nlohmann::json energy_pj(double leakage_pj) const;
  // The unit kind of a line, from its name's prefix: "pe." -> search_units, "ru." ->
  // recursion_units, "sram.<buffer>." -> <buffer>, any other "<x>." -> <x> (node_cache,
  // leader_buffer, dram).
  static std::string unit_of(const std::string& line);

 private:
  struct Line {
    Component component;
    double pj;
    Counter count;
  };
  const EnergyTable& table_;
  StatGroup stats_;
  std::vector<std::unique_ptr<Line>> lines_;
};

}  // namespace tigris::hw
