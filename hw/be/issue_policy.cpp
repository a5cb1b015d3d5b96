#include "hw/be/issue_policy.hpp"

#include "hw/be/mqmn_policy.hpp"
#include "hw/be/mqsn_policy.hpp"

namespace tigris::hw {

std::unique_ptr<IssuePolicy> make_issue_policy(const AcceleratorConfig& config) {
  if (config.be.issue_policy == IssuePolicyKind::Mqmn) return std::make_unique<MqmnPolicy>();
  return std::make_unique<MqsnPolicy>(config.be.issue_search_width);
}

}  // namespace tigris::hw
