#include "run_report.hpp"

#include <algorithm>

namespace tigris {

namespace {

nlohmann::json buffer_json(const hw::BufferStats& s) {
  return {{"reads", s.reads}, {"writes", s.writes}, {"read_bytes", s.read_bytes},
          {"write_bytes", s.write_bytes}, {"conflict_cycles", s.conflict_cycles}};
}

double ratio(double a, double b) { return b > 0 ? a / b : 0.0; }

}  // namespace

nlohmann::json units_json(const hw::TigrisAccelerator& accel, std::uint64_t cycles) {
  const auto& cfg = accel.config();
  hw::RecursionUnitStats ru;
  for (const auto& r : accel.fe.rus) {
    const auto& s = r->stats();
    ru.activations += s.activations, ru.busy_cycles += s.busy_cycles;
    ru.pi_rs_stall_cycles += s.pi_rs_stall_cycles, ru.prune_cycles += s.prune_cycles;
    ru.sram_stall_cycles += s.sram_stall_cycles, ru.bqb_full_stall_cycles += s.bqb_full_stall_cycles;
    ru.writeback_stall_cycles += s.writeback_stall_cycles;
    ru.nodes += s.nodes, ru.pruned += s.pruned;
  }
  hw::SearchUnitStats su;
  for (const auto& u : accel.sus) {
    const auto& s = u->stats();
    su.batches += s.batches, su.queries += s.queries, su.busy_cycles += s.busy_cycles;
    su.issue_cycles += s.issue_cycles, su.sram_stall_cycles += s.sram_stall_cycles;
    su.pe_busy_cycles += s.pe_busy_cycles;
    su.writeback_stall_cycles += s.writeback_stall_cycles;
    su.bqb_max_occupancy = std::max(su.bqb_max_occupancy, s.bqb_max_occupancy);
  }
  const double n_ru = cfg.fe.recursion_units, n_su = cfg.be.search_units;
  const double n_pe = n_su * cfg.be.pes_per_su, c = static_cast<double>(cycles);
  return {
      {"recursion_units",
       {{"count", cfg.fe.recursion_units},
        {"activations", ru.activations},
        {"nodes", ru.nodes},
        {"pruned", ru.pruned},
        {"busy_cycles", ru.busy_cycles},
        {"utilization", ratio(static_cast<double>(ru.busy_cycles), n_ru * c)},
        {"stall_cycles",
         {{"pi_rs_dependency", ru.pi_rs_stall_cycles},
          {"sram", ru.sram_stall_cycles},
          {"bqb_full", ru.bqb_full_stall_cycles},
          {"result_writeback", ru.writeback_stall_cycles}}},
        {"prune_cycles", ru.prune_cycles}}},
      {"search_units",
       {{"count", cfg.be.search_units},
        {"pes_per_su", cfg.be.pes_per_su},
        {"issue_policy", hw::to_string(cfg.be.issue_policy)},
        {"batches", su.batches},
        {"queries", su.queries},
        {"queries_per_batch", ratio(static_cast<double>(su.queries), static_cast<double>(su.batches))},
        {"busy_cycles", su.busy_cycles},
        {"utilization", ratio(static_cast<double>(su.busy_cycles), n_su * c)},
        {"pe_utilization", ratio(static_cast<double>(su.pe_busy_cycles), n_pe * c)},
        {"stall_cycles",
         {{"issue_search", su.issue_cycles},
          {"sram", su.sram_stall_cycles},
          {"result_writeback", su.writeback_stall_cycles}}},
        {"bqb_max_occupancy", su.bqb_max_occupancy},
        {"queries_per_unit", [&] {
           std::vector<std::uint64_t> v;
           for (const auto& u : accel.sus) v.push_back(u->stats().queries);
           return v;
         }()}}},
      {"qdn", {{"queries", accel.qdn.stats().queries}, {"port_wait_cycles", accel.qdn.stats().port_wait_cycles}}},
      {"fqq", {{"max_occupancy", accel.fe.fqq_max_occupancy()}, {"queries_in_flight", accel.job().slots}}},
      {"result_writeback", {{"bytes", accel.dram.bytes()}, {"stall_cycles", accel.dram.stall_cycles()}}}};
}

nlohmann::json buffers_json(const hw::TigrisAccelerator& accel) {
  const auto& nc = accel.node_cache.stats();
  return {{"points", buffer_json(accel.points_sram.stats())},
          {"queries", buffer_json(accel.queries_sram.stats())},
          {"query_stack", buffer_json(accel.stack_sram.stats())},
          {"results", buffer_json(accel.results_sram.stats())},
          {"node_cache", {{"hits", nc.hits}, {"misses", nc.misses}, {"read_bytes", nc.read_bytes}, {"fill_bytes", nc.fill_bytes}}},
          {"dram", {{"writes", 0}, {"reads", 0}, {"read_bytes", 0}, {"write_bytes", accel.dram.bytes()}}}};
}

nlohmann::json energy_json(const hw::TigrisAccelerator& accel) {
  const auto& e = accel.config().energy;
  std::uint64_t distances = 0;
  for (const auto& c : accel.job().counters) distances += std::uint64_t{c.top} + c.leaf_points;
  double sram_read = 0, sram_write = 0;
  for (const hw::BankedSram* b : {&accel.points_sram, &accel.queries_sram, &accel.stack_sram, &accel.results_sram}) {
    sram_read += static_cast<double>(b->stats().read_bytes) * e.sram_read_pj_per_byte;
    sram_write += static_cast<double>(b->stats().write_bytes) * e.sram_write_pj_per_byte;
  }
  const double pe = static_cast<double>(distances) * e.distance_pj;
  const double cache = static_cast<double>(accel.node_cache.stats().read_bytes + accel.node_cache.stats().fill_bytes) * e.node_cache_pj_per_byte;
  const double dram = static_cast<double>(accel.dram.bytes()) * e.dram_pj_per_byte;
  return {{"distance", pe}, {"sram_read", sram_read}, {"sram_write", sram_write},
          {"node_cache", cache}, {"dram", dram}, {"total", pe + sram_read + sram_write + cache + dram}};
}

double lower_bound_cycles(const hw::TigrisAccelerator& accel) {
  std::uint64_t top = 0, leaf = 0;
  for (const auto& c : accel.job().counters) top += c.top, leaf += c.leaf_points;
  const auto& cfg = accel.config();
  return std::max(static_cast<double>(top) / cfg.fe.recursion_units,
                  static_cast<double>(leaf) / (static_cast<double>(cfg.be.search_units) * cfg.be.pes_per_su));
}

}  // namespace tigris
