// The energy, power and area models (docs/model.md): the default area is the paper's,
// each count and size key scales its own block, SRAM prices follow the bank-size rule, and a
// tiny job's energy is its counts times the table's prices plus leakage over its area.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>

#include "hw/area_model.hpp"
#include "hw/energy_meter.hpp"
#include "sw_ref/search.hpp"
#include "test_util.hpp"
#include "testbench/simulation.hpp"

using namespace tigris;
using namespace tigris::test;
using hw::AcceleratorConfig;

namespace {

constexpr double kMiB = 1048576.0;

std::map<std::string, double> blocks(const hw::Area& a) {
  std::map<std::string, double> m;
  for (const auto* list : {&a.sram, &a.logic})
    for (const hw::Area::Block& b : *list) m[b.name] = b.mm2;
  return m;
}

// `changed`'s area differs from the default's by exactly `delta` mm2 per named block, and in no
// other block.
void check_delta(const AcceleratorConfig& changed, const std::map<std::string, double>& delta) {
  const auto before = blocks(hw::area_of(AcceleratorConfig{}));
  const auto after = blocks(hw::area_of(changed));
  REQUIRE(before.size() == after.size());
  for (const auto& [name, mm2] : before) {
    INFO("block " << name);
    const auto d = delta.find(name);
    CHECK(after.at(name) - mm2 == Approx(d == delta.end() ? 0.0 : d->second).margin(1e-12));
  }
}

}  // namespace

TEST_CASE("area: the default configuration is the paper's 8.38 mm2 SRAM and 7.19 mm2 logic", "[area]") {
  const hw::Area a = hw::area_of(AcceleratorConfig{});
  // Within 0.005 mm2: the table's defaults are rounded to 3-4 digits.
  CHECK(a.sram_mm2() == Approx(8.38).margin(0.005));
  CHECK(a.logic_mm2() == Approx(7.19).margin(0.005));
  CHECK(a.total_mm2() == Approx(a.sram_mm2() + a.logic_mm2()));
  CHECK(a.of("pes") == Approx(1024 * 0.006));
  CHECK(a.of("recursion_units") == Approx(64 * 0.0075));
  // Every buffer has its block; 2^10 leaves x 16 leaders x 12 bytes of Leader Buffer.
  for (const char* b : {"points", "queries", "query_stack", "results", "fqq", "bqb", "node_cache", "leader_buffer"})
    CHECK(a.of(b) > 0);
  CHECK(hw::leader_buffer_bytes(AcceleratorConfig{}) == 1024 * 16 * 12);
  const nlohmann::json j = a.to_json();
  CHECK(j["sram"].get<double>() == a.sram_mm2());
  CHECK(j["by_block"]["sram"]["points"].get<double>() == a.of("points"));
  CHECK(j["by_block"]["logic"]["issue_logic"].get<double>() == a.of("issue_logic"));
}

TEST_CASE("area: doubling a count or size key grows its own block by what it adds", "[area]") {
  const AcceleratorConfig d;
  const hw::AreaTable& t = d.area;
  const double per_byte = t.sram_mm2_per_mib / kMiB;
  AcceleratorConfig c = d;

  c.fe.recursion_units *= 2;
  check_delta(c, {{"recursion_units", 64 * t.ru_mm2}});
  c = d, c.be.pes_per_su *= 2;
  check_delta(c, {{"pes", 1024 * t.pe_mm2}});
  // More SUs: more PEs, issue logic and BQBs, and one more Node Cache and Leader Buffer bank each.
  c = d, c.be.search_units *= 2;
  check_delta(c, {{"pes", 1024 * t.pe_mm2},
                  {"issue_logic", 32 * t.issue_logic_mm2},
                  {"bqb", hw::area_of(d).of("bqb")},
                  {"node_cache", 32 * t.sram_bank_mm2},
                  {"leader_buffer", 32 * t.sram_bank_mm2}});
  c = d, c.sram.points.bytes *= 2;
  check_delta(c, {{"points", 2097152 * per_byte}});
  c = d, c.sram.points.banks *= 2;
  check_delta(c, {{"points", 128 * t.sram_bank_mm2}});
  c = d, c.sram.queries.bytes *= 2;
  check_delta(c, {{"queries", 1572864 * per_byte}});
  c = d, c.sram.query_stack.banks *= 2;
  check_delta(c, {{"query_stack", 64 * t.sram_bank_mm2}});
  c = d, c.sram.results.bytes *= 2;
  check_delta(c, {{"results", 3145728 * per_byte}});
  c = d, c.fe.fqq_bytes *= 2;
  check_delta(c, {{"fqq", 1572864 * per_byte}});
  c = d, c.be.bqb_entries *= 2;
  check_delta(c, {{"bqb", 32 * 1024 * per_byte}});
  c = d, c.be.bqb_entry_bytes *= 2;
  check_delta(c, {{"bqb", 32 * 1024 * per_byte}});
  c = d, c.node_cache.bytes *= 2;
  check_delta(c, {{"node_cache", 131072 * per_byte}});
  c = d, c.leader.capacity_per_leaf *= 2;
  check_delta(c, {{"leader_buffer", 196608 * per_byte}});
  c = d, c.tree.top_height += 1;  // twice the leaves
  check_delta(c, {{"leader_buffer", 196608 * per_byte}});
  // The table's own keys.
  c = d, c.area.pe_mm2 *= 2;
  check_delta(c, {{"pes", 1024 * t.pe_mm2}});
  c = d, c.area.sram_bank_mm2 *= 2;
  check_delta(c, {{"points", 128 * t.sram_bank_mm2},
                  {"queries", 8 * t.sram_bank_mm2},
                  {"query_stack", 64 * t.sram_bank_mm2},
                  {"results", 64 * t.sram_bank_mm2},
                  {"fqq", t.sram_bank_mm2},
                  {"bqb", 32 * t.sram_bank_mm2},
                  {"node_cache", 32 * t.sram_bank_mm2},
                  {"leader_buffer", 32 * t.sram_bank_mm2}});
  // Off or absent: no Node Cache, no Leader Buffer for a canonical tree.
  c = d, c.node_cache.bytes = 0;
  CHECK(hw::area_of(c).of("node_cache") == 0.0);
  c = d, c.tree.top_height = -1;
  CHECK(hw::area_of(c).of("leader_buffer") == 0.0);
  // Leakage is the table's price x area x cycles.
  CHECK(hw::leakage_pj(d, 1000) == Approx(4.0 * hw::area_of(d).total_mm2() * 1000));
}

TEST_CASE("energy: SRAM prices follow the bank size by the square-root rule", "[energy]") {
  const hw::EnergyTable t;
  // The reference point: 8 KB banks at 0.35 pJ/byte (Horowitz 10 pJ per 64 bits x 0.28).
  CHECK(t.sram_price(8192 * 4, 4, false) == Approx(0.35));
  // Default Point Buffer: 2 MiB in 128 banks = 16 KB banks: x sqrt(2).
  CHECK(t.sram_price(2097152, 128, false) == Approx(0.35 * std::sqrt(2.0)));
  // 4x the bank, 2x the energy (Horowitz: 8 KB 10 pJ, 32 KB 20 pJ).
  CHECK(t.sram_price(32768, 1, false) == Approx(2 * t.sram_price(8192, 1, false)));
  // More banks of the same capacity: smaller banks, cheaper accesses.
  CHECK(t.sram_price(1 << 20, 64, false) == Approx(t.sram_price(1 << 20, 16, false) / 2));
  hw::EnergyTable w = t;
  w.sram_write_factor = 1.5;
  CHECK(w.sram_price(65536, 2, true) == Approx(1.5 * w.sram_price(65536, 2, false)));
  w.sram_size_exponent = 0;  // one price for every buffer
  CHECK(w.sram_price(3145728, 1, false) == Approx(0.35));
  // The Leader Buffer default is the rule at its default 6 KB bank per SU.
  CHECK(t.leader_buffer_pj_per_byte ==
        Approx(t.sram_price(hw::leader_buffer_bytes(AcceleratorConfig{}), 32, false)).epsilon(0.02));
}

TEST_CASE("energy: a tiny job's energy is its counts x the table's prices, plus leakage", "[hw][energy]") {
  const PointCloud cloud = make_cloud(CloudKind::Uniform, 600, 11);
  const PointCloud queries = make_queries(cloud, 50, 11);
  AcceleratorConfig cfg;
  cfg.fe.recursion_units = 2, cfg.be.search_units = 2, cfg.be.pes_per_su = 4, cfg.tree.top_height = 3;
  // Round prices, and buffers whose banks are 4x, 16x the 4 KB reference bank: 2x, 4x its price.
  hw::EnergyTable& e = cfg.energy;
  e.distance_pj = 2, e.ru_node_pj = 3, e.sram_ref_pj_per_byte = 1, e.sram_ref_bank_bytes = 4096;
  e.sram_write_factor = 1.5, e.dram_pj_per_byte = 10, e.leakage_pj_per_mm2_cycle = 0.5;
  cfg.sram.points.bytes = 2097152, cfg.sram.points.banks = 128;           // 16 KB banks: 2 pJ/B
  cfg.sram.queries.bytes = 1048576, cfg.sram.queries.banks = 16;          // 64 KB: 4 pJ/B
  cfg.sram.query_stack.bytes = 1048576, cfg.sram.query_stack.banks = 64;  // 16 KB: 2 pJ/B
  cfg.sram.results.bytes = 3145728, cfg.sram.results.banks = 48;          // 64 KB: 4 pJ/B
  cfg.node_cache.bytes = 131072;                                          // 2 SU banks of 64 KB: 4
  SearchParams p;
  p.mode = Mode::KNN, p.k = 3;

  const KdTree tree = build_kdtree(cloud, cfg.tree.top_height);
  const tlm_if::TreeImage image = tlm_if::encode_tree_image(tree);
  SimSetup s;
  s.config = cfg, s.image = &image, s.queries = &queries;
  s.num_points = static_cast<std::uint32_t>(cloud.size());
  s.job = host_job(p);
  const SimOutcome o = simulate({s}).front();
  REQUIRE(o.finished);

  const auto& b = o.buffers;
  const auto bytes = [&](const char* buffer, const char* counter) { return b.at(buffer).at(counter).get<double>(); };
  const double cycles = static_cast<double>(o.cycles);
  REQUIRE(o.visits.visits.leaf_points > 0);
  REQUIRE(bytes("dram", "write_bytes") > 0);
  REQUIRE(bytes("node_cache", "fill_bytes") > 0);
  const double pe = 2.0 * static_cast<double>(o.visits.visits.leaf_points);
  const double ru = 3.0 * static_cast<double>(o.visits.visits.top);
  const double points = 2 * bytes("points", "read_bytes") + 3 * bytes("points", "write_bytes");
  const double queries_pj = 4 * bytes("queries", "read_bytes") + 6 * bytes("queries", "write_bytes");
  const double stack = 2 * bytes("query_stack", "read_bytes") + 3 * bytes("query_stack", "write_bytes");
  const double results = 4 * bytes("results", "read_bytes") + 6 * bytes("results", "write_bytes");
  const double read = 2 * bytes("points", "read_bytes") + 4 * bytes("queries", "read_bytes") +
                      2 * bytes("query_stack", "read_bytes") + 4 * bytes("results", "read_bytes");
  const double write = points + queries_pj + stack + results - read;
  const double node_cache = 4 * (bytes("node_cache", "read_bytes") + bytes("node_cache", "fill_bytes"));
  const double dram = 10 * bytes("dram", "write_bytes");
  const double leakage = 0.5 * hw::area_of(cfg).total_mm2() * cycles;
  const double total = pe + ru + read + write + node_cache + dram + leakage;

  const auto& j = o.energy;
  CHECK(j["pe"].get<double>() == Approx(pe));
  CHECK(j["ru"].get<double>() == Approx(ru));
  CHECK(j["sram_read"].get<double>() == Approx(read));
  CHECK(j["sram_write"].get<double>() == Approx(write));
  CHECK(j["node_cache"].get<double>() == Approx(node_cache));
  CHECK(j["leader_buffer"].get<double>() == 0.0);  // exact search
  CHECK(j["dram"].get<double>() == Approx(dram));
  CHECK(j["leakage"].get<double>() == Approx(leakage));
  CHECK(j["total"].get<double>() == Approx(total));
  const auto& u = j["by_unit"];
  CHECK(u["search_units"].get<double>() == Approx(pe));
  CHECK(u["recursion_units"].get<double>() == Approx(ru));
  CHECK(u["points"].get<double>() == Approx(points));
  CHECK(u["queries"].get<double>() == Approx(queries_pj));
  CHECK(u["query_stack"].get<double>() == Approx(stack));
  CHECK(u["results"].get<double>() == Approx(results));
  CHECK(u["node_cache"].get<double>() == Approx(node_cache));
  CHECK(u["dram"].get<double>() == Approx(dram));
  CHECK(u["leakage"].get<double>() == Approx(leakage));
  double by_unit = 0;
  for (const auto& [unit, pj] : u.items()) by_unit += pj.get<double>();
  CHECK(by_unit == Approx(total));
  // Power: the total over the job's time at 500 MHz.
  CHECK(o.power_w.get<double>() == Approx(total * 1e-12 / (cycles / 500e6)));
  CHECK(o.area["total"].get<double>() == Approx(hw::area_of(cfg).total_mm2()));
}

TEST_CASE("energy: lines belong to the unit kind their name starts with", "[energy]") {
  CHECK(hw::EnergyMeter::unit_of("pe.distance") == "search_units");
  CHECK(hw::EnergyMeter::unit_of("pe.leader_check") == "search_units");
  CHECK(hw::EnergyMeter::unit_of("ru.node") == "recursion_units");
  CHECK(hw::EnergyMeter::unit_of("sram.query_stack.write_bytes") == "query_stack");
  CHECK(hw::EnergyMeter::unit_of("node_cache.bytes") == "node_cache");
  CHECK(hw::EnergyMeter::unit_of("leader_buffer.read_bytes") == "leader_buffer");
  CHECK(hw::EnergyMeter::unit_of("dram.write_bytes") == "dram");
}
