#include "run_report.hpp"

#include <algorithm>
#include <cstdio>

#include "config.hpp"
#include "config/key_table.hpp"
#include "hw/area_model.hpp"
#include "stat_formulas.hpp"

namespace tigris {

namespace {

using nlohmann::json;

double ratio(double a, double b) { return b > 0 ? a / b : 0.0; }

}  // namespace

const std::vector<Placement>& placements() {
  static const std::vector<Placement> table = {
      {"recursion_unit", "units.recursion_units", true},
      {"search_unit", "units.search_units", true},
      {"qdn", "units.qdn", false},
      {"front_end", "units.fqq", false},  // the FE's counters are its Query Queue's
      {"buffer", "buffers.{name}", false},
      {"node_cache", "buffers.node_cache", false},
      {"leader_buffer", "buffers.leader_buffer", false},  // one per SU, summed
      {"dram", "buffers.dram", false},
  };
  return table;
}

std::string placed_at(const Placement& p, const hw::StatGroup& group) {
  std::string path = p.path;
  if (const std::size_t at = path.find("{name}"); at != std::string::npos) path.replace(at, 6, group.name());
  return path;
}

json run_stats_json(const hw::TigrisAccelerator& accel, std::uint64_t cycles) {
  const hw::AcceleratorConfig& cfg = accel.config();
  const hw::StatGroup& root = accel.stats();
  json j = json::object();
  for (const Placement& p : placements()) {
    const auto groups = root.find(p.kind);
    if (groups.empty()) throw std::logic_error(std::string("no statistics group of kind '") + p.kind + "'");
    if (std::string(p.path).find("{name}") != std::string::npos) {
      for (const hw::StatGroup* g : groups) j[config::pointer(placed_at(p, *g))] = g->counters_json();
      continue;
    }
    json& at = j[config::pointer(p.path)];
    if (at.is_null()) at = json::object();
    at.update(hw::StatGroup::sum(groups), true);
    if (p.per_unit) {
      at["per_unit"] = json::array();
      for (const hw::StatGroup* g : groups) at["per_unit"].push_back(g->counters_json());
    }
  }
  json& ru = j["units"]["recursion_units"];
  ru["count"] = cfg.fe.recursion_units;
  json& su = j["units"]["search_units"];
  su["count"] = cfg.be.search_units;
  su["pes_per_su"] = cfg.be.pes_per_su;
  su["issue_policy"] = cfg.be.issue_policy;
  j["buffers"]["node_cache"]["policy"] = cfg.node_cache.policy;
  j["energy_pj"] = accel.energy_pj(hw::leakage_pj(cfg, cycles));
  j["area_mm2"] = hw::area_of(cfg).to_json();
  // The derived fields (utilizations, seconds, power) from their formulas, over these fields.
  j["cycles"] = cycles;
  j["config"] = config_to_json(cfg);
  add_derived(j);
  j.erase("config");
  return j;
}

std::string energy_area_summary(const json& stats) {
  const json& e = stats.at("energy_pj");
  const json& a = stats.at("area_mm2");
  const double total = e.at("total").get<double>();
  const auto pct = [&](const char* c) { return 100 * ratio(e.at(c).get<double>(), total); };
  // Above 10 mJ in mJ: "3.313e+04 uJ" reads badly.
  const bool milli = total >= 1e10;
  const double scale = milli ? 1e-9 : 1e-6;
  const char* unit = milli ? "mJ" : "uJ";
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "  energy  %.4g %s: PE %.1f%%, RU %.1f%%, SRAM read %.1f%%, SRAM write %.1f%%, Node Cache "
                "%.1f%%, Leader Buffer %.1f%%, DRAM %.1f%%, leakage %.1f%% (%.4g %s)\n"
                "  power   %.3g W\n"
                "  area    %.2f mm2: SRAM %.2f, logic %.2f\n",
                total * scale, unit, pct("pe"), pct("ru"), pct("sram_read"), pct("sram_write"), pct("node_cache"),
                pct("leader_buffer"), pct("dram"), pct("leakage"), e.at("leakage").get<double>() * scale, unit,
                stats.at("power_w").get<double>(), a.at("total").get<double>(), a.at("sram").get<double>(),
                a.at("logic").get<double>());
  return buf;
}

}  // namespace tigris
