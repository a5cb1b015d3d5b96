#include "node_cache.hpp"

#include "hw/area_model.hpp"

namespace tigris::hw {

NodeCache::NodeCache(sc_core::sc_module_name name, const AcceleratorConfig& config, EnergyMeter& meter)
    : sc_module(name), capacity_(config.node_cache.bytes), policy_(make_replacement_policy(config)),
      // Priced by the SRAM rule at its bank size; a fill is charged as a read (equal by default).
      energy_(meter.line("node_cache.bytes", EnergyMeter::Component::NodeCache,
                         meter.table().sram_price(config.node_cache.bytes, per_su_banks(config), false))) {}

void NodeCache::start() {
  sets_.clear();
  policy_->reset();
  used_ = 0;
}

bool NodeCache::lookup(std::uint32_t leaf, std::uint64_t bytes) {
  if (!enabled()) return false;
  if (sets_.count(leaf)) {
    policy_->hit(leaf);
    ++hits_;
    read_bytes_ += bytes;
    energy_ += bytes;
    return true;
  }
  ++misses_;
  if (bytes > capacity_) return false;
  while (used_ + bytes > capacity_) {
    const std::uint32_t victim = policy_->evict();
    used_ -= sets_.at(victim);
    sets_.erase(victim);
    ++evictions_;
  }
  sets_[leaf] = bytes;
  policy_->inserted(leaf, bytes);
  used_ += bytes;
  fill_bytes_ += bytes;
  energy_ += bytes;
  return false;
}

}  // namespace tigris::hw
