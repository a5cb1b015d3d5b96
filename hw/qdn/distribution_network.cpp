#include "distribution_network.hpp"

#include <algorithm>

#include "hw/be/search_unit.hpp"
#include "hw/fe/recursion_unit.hpp"

namespace tigris::hw {

DistributionNetwork::DistributionNetwork(sc_core::sc_module_name name, const AcceleratorConfig& config,
                                         JobObserver& observer)
    : sc_module(name), cost_(config.cost), observer_(observer), stall_(config.stall, "qdn", stats_) {}

void DistributionNetwork::connect(std::vector<SearchUnit*> units) {
  units_ = std::move(units);
  start();
}

void DistributionNetwork::start() {
  stall_.start();
  port_free_.assign(units_.size(), 0);
  waiting_.assign(units_.size(), {});
}

std::uint64_t DistributionNetwork::arrival(std::uint32_t su, std::uint64_t now) {
  const std::uint64_t earliest = now + static_cast<std::uint64_t>(cost_.qdn_latency) + stall_.draw();
  const std::uint64_t at = std::max(earliest, port_free_[su]);
  port_wait_ += at - earliest;
  port_free_[su] = at + static_cast<std::uint64_t>(cost_.qdn_port_interval);
  return at;
}

void DistributionNetwork::send_leader(LeaderRecord record, std::uint64_t now) {
  const std::uint32_t su = target(record.leaf);
  record.ready = arrival(su, now);
  units_[su]->leader_arrives(std::move(record));
}

bool DistributionNetwork::route(const QueryToken& token, std::uint64_t now, RecursionUnit& from) {
  const std::uint32_t su = target(token.leaf);
  if (!units_[su]->has_room()) {
    waiting_[su].push_back(&from);
    return false;
  }
  const std::uint64_t arrival = this->arrival(su, now);
  QueryToken t = token;
  t.ready = arrival;
  observer_.qdn_hop(su, token.query, now, arrival);
  units_[su]->accept(t);
  return true;
}

void DistributionNetwork::space_freed(std::uint32_t su) {
  // Wake as many waiting Recursion Units as there is room; they retry in order.
  std::size_t room = units_[su]->room();
  while (room-- > 0 && !waiting_[su].empty()) {
    waiting_[su].front()->retry_dispatch();
    waiting_[su].pop_front();
  }
}

}  // namespace tigris::hw
