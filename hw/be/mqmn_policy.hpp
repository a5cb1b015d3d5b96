// MQMN (multi-query, multi Node Set): every arrived query goes to a free PE at once, each PE
// streaming its own query's Node Set; no associative search.
#pragma once

#include "hw/be/issue_policy.hpp"

namespace tigris::hw {

class MqmnPolicy final : public IssuePolicy {
 public:
  void pick(const IssueView& view, IssueDecision& d) override;
};

}  // namespace tigris::hw
