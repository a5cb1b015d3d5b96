#include "run_report.hpp"

#include <algorithm>

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

  json ru = unit_kind(root, "recursion_unit", cfg.fe.recursion_units);
  ru["utilization"] = ratio(static_cast<double>(at(ru, "/busy_cycles")), cfg.fe.recursion_units * c);
  json su = unit_kind(root, "search_unit", cfg.be.search_units);
  su["pes_per_su"] = cfg.be.pes_per_su;
  su["issue_policy"] = hw::to_string(cfg.be.issue_policy);
  su["queries_per_batch"] = ratio(static_cast<double>(at(su, "/queries")), static_cast<double>(at(su, "/batches")));
  su["utilization"] = ratio(static_cast<double>(at(su, "/busy_cycles")), cfg.be.search_units * c);
  su["pe_utilization"] = ratio(static_cast<double>(at(su, "/pe_busy_cycles")),
                               static_cast<double>(cfg.be.search_units) * cfg.be.pes_per_su * c);

  json buffers = json::object();
  for (const hw::StatGroup* b : root.find("buffer")) buffers[b->name()] = b->counters_json();
  buffers["node_cache"] = child(root, "node_cache").counters_json();
  buffers["node_cache"]["policy"] = hw::to_string(cfg.node_cache.policy);
  buffers["leader_buffer"] = hw::StatGroup::sum(root.find("leader_buffer"));  // all SUs' together
  buffers["dram"] = child(root, "dram").counters_json();

  return {{"units",
           {{"recursion_units", ru},
            {"search_units", su},
            {"qdn", child(root, "qdn").counters_json()},
            {"fqq", child(root, "fe").counters_json()["fqq"]}}},
          {"buffers", buffers},
          {"energy_pj", accel.energy_pj()}};
}

double lower_bound_cycles(const hw::AcceleratorConfig& cfg, const VisitTotals& v) {
  return std::max(static_cast<double>(v.top) / cfg.fe.recursion_units,
                  static_cast<double>(v.leaf_points) / (static_cast<double>(cfg.be.search_units) * cfg.be.pes_per_su));
}

}  // namespace tigris
