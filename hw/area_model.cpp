#include "area_model.hpp"

#include <algorithm>

#include "hw/be/leader_buffer.hpp"
#include "tlm/tree_image.hpp"

namespace tigris::hw {

namespace {

double sum(const std::vector<Area::Block>& blocks) {
  double s = 0;
  for (const Area::Block& b : blocks) s += b.mm2;
  return s;
}

}  // namespace

std::uint64_t leader_buffer_bytes(const AcceleratorConfig& c) {
  if (c.tree.top_height < 0) return 0;
  return (std::uint64_t{1} << c.tree.top_height) * static_cast<std::uint64_t>(c.leader.capacity_per_leaf) *
         LeaderBuffer::kLeaderBytes;
}

std::uint64_t replicated_top_bytes(const AcceleratorConfig& c) {
  const int levels =
      c.tree.top_height < 0 ? c.fe.top_levels_replicated : std::min(c.fe.top_levels_replicated, c.tree.top_height);
  return ((std::uint64_t{1} << levels) - 1) * sizeof(tlm_if::PointEntry);
}

double Area::sram_mm2() const { return sum(sram); }
double Area::logic_mm2() const { return sum(logic); }

double Area::of(const std::string& block) const {
  for (const auto* blocks : {&sram, &logic})
    for (const Block& b : *blocks)
      if (b.name == block) return b.mm2;
  return 0.0;
}

nlohmann::json Area::to_json() const {
  nlohmann::json by = {{"sram", nlohmann::json::object()}, {"logic", nlohmann::json::object()}};
  for (const Block& b : sram) by["sram"][b.name] = b.mm2;
  for (const Block& b : logic) by["logic"][b.name] = b.mm2;
  return {{"sram", sram_mm2()}, {"logic", logic_mm2()}, {"total", total_mm2()}, {"by_block", by}};
}

Area area_of(const AcceleratorConfig& c) {
  const AreaTable& t = c.area;
  const int sus = c.be.search_units;
  // A buffer of `bytes` in `banks` banks; an empty one (Node Cache off) has no banks either.
  const auto sram = [&](std::uint64_t bytes, int banks) {
    return bytes == 0 ? 0.0 : static_cast<double>(bytes) / 1048576.0 * t.sram_mm2_per_mib + banks * t.sram_bank_mm2;
  };
  const std::uint64_t bqb =
      static_cast<std::uint64_t>(c.be.bqb_entries) * static_cast<std::uint64_t>(c.be.bqb_entry_bytes);
  Area a;
  a.sram = {{"points", sram(c.sram.points.bytes, c.sram.points.banks)},
            {"queries", sram(c.sram.queries.bytes, c.sram.queries.banks)},
            {"query_stack", sram(c.sram.query_stack.bytes, c.sram.query_stack.banks)},
            {"results", sram(c.sram.results.bytes, c.sram.results.banks)},
            {"fqq", sram(c.fe.fqq_bytes, 1)},
            {"bqb", sus * sram(bqb, 1)},
            {"node_cache", sram(c.node_cache.bytes, per_su_banks(c))},
            {"leader_buffer", sram(leader_buffer_bytes(c), per_su_banks(c))},
            {"top_level_replicas",
             c.fe.recursion_units * static_cast<double>(replicated_top_bytes(c)) / 1024.0 * t.register_mm2_per_kib}};
  a.logic = {{"recursion_units", c.fe.recursion_units * t.ru_mm2},
             {"pes", static_cast<double>(sus) * c.be.pes_per_su * t.pe_mm2},
             {"issue_logic", sus * t.issue_logic_mm2}};
  return a;
}

double leakage_pj(const AcceleratorConfig& c, std::uint64_t cycles) {
  return c.energy.leakage_pj_per_mm2_cycle * area_of(c).total_mm2() * static_cast<double>(cycles);
}

}  // namespace tigris::hw
