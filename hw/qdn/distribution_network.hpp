// Query Distribution Network (paper section 5.3): hard-wired leaf id low-order bits -> Search
// Unit (leaf mod #SU), one query per cycle per SU port. A query whose BE Query Buffer is full
// stays in its Recursion Unit, which the network wakes when an entry frees.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "hw/config.hpp"
#include "hw/job.hpp"
#include "hw/stats.hpp"

namespace tigris::hw {

class RecursionUnit;
class SearchUnit;

class DistributionNetwork {
 public:
  DistributionNetwork(const AcceleratorConfig& config, Job& job);

  void connect(std::vector<SearchUnit*> units);
  void reset();
  std::uint32_t target(std::uint32_t leaf) const { return leaf % static_cast<std::uint32_t>(units_.size()); }
  // Sends `token` at cycle `now`; false when the target's BE Query Buffer is full (`from`
  // is then woken through retry_dispatch() when it has room).
  bool route(const QueryToken& token, std::uint64_t now, RecursionUnit& from);
  void space_freed(std::uint32_t su);  // a Search Unit issued queries out of its buffer
  const QdnStats& stats() const { return stats_; }

 private:
  const CostTable& cost_;
  Job& job_;
  std::vector<SearchUnit*> units_;
  std::vector<std::uint64_t> port_free_;
  std::vector<std::deque<RecursionUnit*>> waiting_;
  QdnStats stats_;
};

}  // namespace tigris::hw
