// Node Cache (paper section 5.3): entries hold whole Node Sets, read as FIFOs; a lookup is by
// leaf id, the replacement policy (node_cache.policy: LRU or FIFO, replacement_policy.hpp)
// chooses victims. A Node Set larger than the cache bypasses it. One cache serves every Search
// Unit.
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>

#include <systemc>

#include "hw/config.hpp"
#include "hw/energy_meter.hpp"
#include "hw/stats.hpp"
#include "issue_policy.hpp"
#include "replacement_policy.hpp"

namespace tigris::hw {

class NodeCache : public sc_core::sc_module, public NodeCacheView {
 public:
  NodeCache(sc_core::sc_module_name name, const AcceleratorConfig& config, EnergyMeter& meter);

  void start();  // a job starts cold
  bool enabled() const { return capacity_ > 0; }
  bool resident(std::uint32_t leaf) const override { return sets_.count(leaf) != 0; }  // no side effect
  // True on a hit; on a miss the Node Set is filled (evicting as the policy says).
  bool lookup(std::uint32_t leaf, std::uint64_t bytes);
  StatGroup& stats() { return stats_; }
  std::uint64_t capacity() const { return capacity_; }

 private:
  std::uint64_t capacity_, used_ = 0;
  std::unordered_map<std::uint32_t, std::uint64_t> sets_;  // leaf -> Node Set bytes
  std::unique_ptr<ReplacementPolicy> policy_;
  StatGroup stats_{"node_cache", "node_cache"};
  Counter hits_{stats_, "hits", "count", "Node Sets served from the Node Cache"};
  Counter misses_{stats_, "misses", "count",
                  "Node Sets read from the Point Buffer (and filled, unless larger than the cache)"};
  Counter evictions_{stats_, "evictions", "count", "Node Sets evicted to make room"};
  Counter read_bytes_{stats_, "read_bytes", "bytes", "bytes streamed from the Node Cache on hits"};
  Counter fill_bytes_{stats_, "fill_bytes", "bytes", "bytes written into the Node Cache on misses"};
  Counter& energy_;
};

}  // namespace tigris::hw
