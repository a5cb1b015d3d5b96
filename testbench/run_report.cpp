#include "run_report.hpp"

#include <algorithm>
#include <cstdio>

#include "hw/area_model.hpp"

namespace tigris {

namespace {

using nlohmann::json;

double ratio(double a, double b) { return b > 0 ? a / b : 0.0; }

const hw::StatGroup& child(const hw::StatGroup& g, const std::string& name) {
  for (const hw::StatGroup* c : g.children())
    if (c->name() == name) return *c;
  throw std::logic_error("no statistics group '" + name + "' under '" + g.name() + "'");
}

// The units of one kind: their sums, and each unit's own counters under `per_unit`.
json unit_kind(const hw::StatGroup& root, const std::string& kind, int count) {
  const auto groups = root.find(kind);
  json j = hw::StatGroup::sum(groups);
  j["count"] = count;
  j["per_unit"] = json::array();
  for (const hw::StatGroup* g : groups) j["per_unit"].push_back(g->counters_json());
  return j;
}

std::uint64_t at(const json& j, const char* pointer) { return j.at(json::json_pointer(pointer)).get<std::uint64_t>(); }

}  // namespace

json run_stats_json(const hw::TigrisAccelerator& accel, std::uint64_t cycles) {
  const hw::AcceleratorConfig& cfg = accel.config();
  const hw::StatGroup& root = accel.stats();
  const double c = static_cast<double>(cycles);
  const double seconds = c / (cfg.clock_mhz * 1e6);
  const hw::Area area = hw::area_of(cfg);
  const json energy = accel.energy_pj(hw::leakage_pj(cfg, cycles));

  json ru = unit_kind(root, "recursion_unit", cfg.fe.recursion_units);
  ru["utilization"] = ratio(static_cast<double>(at(ru, "/busy_cycles")), cfg.fe.recursion_units * c);
  json su = unit_kind(root, "search_unit", cfg.be.search_units);
  su["pes_per_su"] = cfg.be.pes_per_su;
  su["issue_policy"] = cfg.be.issue_policy;
  su["queries_per_batch"] = ratio(static_cast<double>(at(su, "/queries")), static_cast<double>(at(su, "/batches")));
  su["utilization"] = ratio(static_cast<double>(at(su, "/busy_cycles")), cfg.be.search_units * c);
  su["pe_utilization"] = ratio(static_cast<double>(at(su, "/pe_busy_cycles")),
                               static_cast<double>(cfg.be.search_units) * cfg.be.pes_per_su * c);

  json buffers = json::object();
  for (const hw::StatGroup* b : root.find("buffer")) buffers[b->name()] = b->counters_json();
  buffers["node_cache"] = child(root, "node_cache").counters_json();
  buffers["node_cache"]["policy"] = cfg.node_cache.policy;
  buffers["leader_buffer"] = hw::StatGroup::sum(root.find("leader_buffer"));  // all SUs' together
  buffers["dram"] = child(root, "dram").counters_json();

  return {{"units",
           {{"recursion_units", ru},
            {"search_units", su},
            {"qdn", child(root, "qdn").counters_json()},
            {"fqq", child(root, "fe").counters_json()["fqq"]}}},
          {"buffers", buffers},
          {"energy_pj", energy},
          {"power_w", seconds > 0 ? energy["total"].get<double>() * 1e-12 / seconds : 0.0},
          {"area_mm2", area.to_json()}};
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

double lower_bound_cycles(const hw::AcceleratorConfig& cfg, const VisitTotals& v) {
  return std::max(static_cast<double>(v.top) / cfg.fe.recursion_units,
                  static_cast<double>(v.leaf_points) / (static_cast<double>(cfg.be.search_units) * cfg.be.pes_per_su));
}

}  // namespace tigris
