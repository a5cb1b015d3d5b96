// MQSN (multi-query, single Node Set): the head of the BE Query Buffer is the search key; the
// associative search checks `be.issue_search_width` entries per cycle and stops once every PE
// has a query of that leaf. The whole array streams one Node Set, so it issues only when every
// PE is free.
#pragma once

#include "hw/be/issue_policy.hpp"

namespace tigris::hw {

class MqsnPolicy final : public IssuePolicy {
 public:
  explicit MqsnPolicy(int search_width) : width_(static_cast<std::uint64_t>(search_width)) {}
  void pick(const IssueView& view, IssueDecision& d) override;

 private:
  std::uint64_t width_;
};

}  // namespace tigris::hw
