// Query Distribution Network (paper section 5.3): hard-wired leaf id low-order bits -> Search
// Unit (leaf mod #SU), one query per cycle per SU port. A query whose BE Query Buffer is full
// stays in its Recursion Unit, which the network wakes when an entry frees.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include <systemc>

#include "hw/be/search_unit.hpp"
#include "hw/config.hpp"
#include "hw/job.hpp"
#include "hw/observer.hpp"
#include "hw/stall_injector.hpp"
#include "hw/stats.hpp"

namespace tigris::hw {

class RecursionUnit;

class DistributionNetwork : public sc_core::sc_module {
 public:
  DistributionNetwork(sc_core::sc_module_name name, const AcceleratorConfig& config, JobObserver& observer);

  void connect(std::vector<SearchUnit*> units);
  void start();  // a job starts: ports free, nobody waiting
  std::uint32_t target(std::uint32_t leaf) const { return leaf % static_cast<std::uint32_t>(units_.size()); }
  // Sends `token` at cycle `now`; false when the target's BE Query Buffer is full (`from`
  // is then woken through retry_dispatch() when it has room).
  bool route(const QueryToken& token, std::uint64_t now, RecursionUnit& from);
  void space_freed(std::uint32_t su);  // a Search Unit issued queries out of its buffer
  // first_leaf: a finished leader's record to the SU owning its first leaf, through that SU's
  // port like a query (it needs no BE Query Buffer entry).
  void send_leader(LeaderRecord record, std::uint64_t now);
  StatGroup& stats() { return stats_; }

 private:
  std::uint64_t arrival(std::uint32_t su, std::uint64_t now);  // the port's next free cycle from `now`
  const CostTable& cost_;
  JobObserver& observer_;
  std::vector<SearchUnit*> units_;
  std::vector<std::uint64_t> port_free_;
  std::vector<std::deque<RecursionUnit*>> waiting_;
  StatGroup stats_{"qdn", "qdn"};
  Counter port_wait_{stats_, "port_wait_cycles", "cycles",
                     "cycles queries waited for their SU's QDN port (one query per cycle per port)"};
  StallInjector stall_;  // QDN -> BQB
};

}  // namespace tigris::hw
