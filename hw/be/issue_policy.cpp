// MQSN: the head of the BE Query Buffer is the search key; the associative search checks
// `issue_search_width` entries per cycle and stops once every PE has a query of that leaf.
#include "hw/be/issue_policy.hpp"

#include <stdexcept>

namespace tigris::hw {

namespace {

class MqsnPolicy final : public IssuePolicy {
 public:
  explicit MqsnPolicy(int width) : width_(static_cast<std::uint64_t>(width)) {}
  bool shared_stream() const override { return true; }
  IssueDecision pick(const std::vector<QueryToken>& bqb, std::uint32_t free_pes,
                     std::uint64_t now) const override {
    IssueDecision d;
    if (bqb.empty() || bqb.front().ready > now) return d;
    const std::uint32_t key = bqb.front().leaf;
    std::size_t scanned = 0;
    for (std::size_t i = 0; i < bqb.size() && d.picks.size() < free_pes; ++i) {
      if (bqb[i].ready > now) break;  // entries arrive in order; later ones are not here yet
      scanned = i + 1;
      if (bqb[i].leaf == key) d.picks.push_back(i);
    }
    d.search_cycles = (scanned + width_ - 1) / width_;
    return d;
  }

 private:
  std::uint64_t width_;
};

class MqmnPolicy final : public IssuePolicy {
 public:
  bool shared_stream() const override { return false; }
  IssueDecision pick(const std::vector<QueryToken>& bqb, std::uint32_t free_pes,
                     std::uint64_t now) const override {
    IssueDecision d;
    for (std::size_t i = 0; i < bqb.size() && d.picks.size() < free_pes && bqb[i].ready <= now; ++i)
      d.picks.push_back(i);
    return d;
  }
};

}  // namespace

std::unique_ptr<IssuePolicy> make_issue_policy(const AcceleratorConfig& config) {
  if (config.be.issue_policy == IssuePolicyKind::Mqsn) return std::make_unique<MqsnPolicy>(config.be.issue_search_width);
  if (config.be.issue_policy == IssuePolicyKind::Mqmn) return std::make_unique<MqmnPolicy>();
  throw std::invalid_argument("be.issue_policy: unknown issue policy");
}

}  // namespace tigris::hw
