#include "energy_meter.hpp"

namespace tigris::hw {

Counter& EnergyMeter::line(const std::string& name, Component component, double pj) {
  for (const auto& l : lines_)
    if (l->count.name() == name) return l->count;  // units of one kind share their line
  lines_.push_back(std::unique_ptr<Line>(new Line{component, pj, Counter(stats_, name)}));
  return lines_.back()->count;
}

nlohmann::json EnergyMeter::energy_pj() const {
  static const char* const names[] = {"pe", "ru", "sram_read", "sram_write", "node_cache", "leader_buffer", "dram"};
  constexpr int kComponents = sizeof(names) / sizeof(names[0]);
  double by[kComponents] = {};
  for (const auto& l : lines_) by[static_cast<int>(l->component)] += static_cast<double>(l->count.value()) * l->pj;
  nlohmann::json j = nlohmann::json::object();
  double total = 0;
  for (int c = 0; c < kComponents; ++c) {
    j[names[c]] = by[c];
    total += by[c];
  }
  j["total"] = total;
  return j;
}

}  // namespace tigris::hw
