// MQMN (multi-query, multi Node Set): every arrived query goes to a free PE at once, each PE
// streaming its own query's Node Set; no associative search.
#include "hw/be/issue_policy.hpp"

namespace tigris::hw {
namespace {

class MqmnIssue final : public IssuePolicy {
 public:
  void pick(const IssueView& v, IssueDecision& d) override {
    d.clear();
    for (std::size_t i = 0; i < v.bqb.size() && d.batches() < v.free_pes && v.bqb[i].ready <= v.now; ++i) {
      d.positions.push_back(i);
      d.end_batch();
    }
  }
};

const bool registered = IssuePolicies::add("mqmn", "any query to any free PE, each streaming its own Node Set",
                                           [](const AcceleratorConfig&) { return std::make_unique<MqmnIssue>(); });

}  // namespace
}  // namespace tigris::hw
