// MQSN (multi-query, single Node Set): the head of the BE Query Buffer is the search key; the
// associative search checks `be.issue_search_width` entries per cycle and stops once every PE
// has a query of that leaf. The whole array streams one Node Set, so it issues only when every
// PE is free.
#include "hw/be/issue_policy.hpp"

namespace tigris::hw {
namespace {

class MqsnIssue final : public IssuePolicy {
 public:
  explicit MqsnIssue(int search_width) : width_(static_cast<std::uint64_t>(search_width)) {}
  void pick(const IssueView& v, IssueDecision& d) override {
    d.clear();
    if (v.free_pes < v.pes || v.bqb.empty() || v.bqb.front().ready > v.now) return;
    const std::uint32_t key = v.bqb.front().leaf;
    std::size_t scanned = 0;
    for (std::size_t i = 0; i < v.bqb.size() && d.positions.size() < v.free_pes; ++i) {
      if (v.bqb[i].ready > v.now) break;  // entries arrive in order; later ones are not here yet
      scanned = i + 1;
      if (v.bqb[i].leaf == key) d.positions.push_back(i);
    }
    d.search_cycles = (scanned + width_ - 1) / width_;
    d.end_batch();
  }

 private:
  std::uint64_t width_;
};

const bool registered = IssuePolicies::add(
    "mqsn", "the head's leaf only, found by an associative search; the whole array streams one Node Set",
    [](const AcceleratorConfig& c) { return std::make_unique<MqsnIssue>(c.be.issue_search_width); });

}  // namespace
}  // namespace tigris::hw
