#include "energy_meter.hpp"

namespace tigris::hw {

Counter& EnergyMeter::line(const std::string& name, Component component, double pj) {
  for (const auto& l : lines_)
    if (l->count.name() == name) return l->count;  // units of one kind share their line
  lines_.push_back(std::unique_ptr<Line>(new Line{
      component, pj,
      Counter(stats_, name, name.size() >= 5 && name.compare(name.size() - 5, 5, "bytes") == 0 ? "bytes" : "count",
              "events priced on the energy line " + name)}));
  return lines_.back()->count;
}

std::string EnergyMeter::unit_of(const std::string& line) {
  const std::string head = line.substr(0, line.find('.'));
  if (head == "pe") return "search_units";
  if (head == "ru") return "recursion_units";
  if (head == "sram") {
    const std::size_t from = head.size() + 1;
    return line.substr(from, line.find('.', from) - from);
  }
  return head;
}

nlohmann::json EnergyMeter::energy_pj(double leakage_pj) const {
  static const char* const names[] = {"pe", "ru", "sram_read", "sram_write", "node_cache", "leader_buffer", "dram"};
  constexpr int kComponents = sizeof(names) / sizeof(names[0]);
  double by[kComponents] = {};
  nlohmann::json by_unit = {{"leakage", leakage_pj}};
  for (const auto& l : lines_) {
    const double pj = static_cast<double>(l->count.value()) * l->pj;
    by[static_cast<int>(l->component)] += pj;
    const std::string unit = unit_of(l->count.name());
    by_unit[unit] = by_unit.value(unit, 0.0) + pj;
  }
  nlohmann::json j = nlohmann::json::object();
  double total = leakage_pj;
  for (int c = 0; c < kComponents; ++c) {
    j[names[c]] = by[c];
    total += by[c];
  }
  j["leakage"] = leakage_pj;
  j["total"] = total;
  j["by_unit"] = by_unit;
  return j;
}

}  // namespace tigris::hw
