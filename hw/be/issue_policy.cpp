#include "issue_policy.hpp"

#include <stdexcept>

namespace tigris::hw {

std::unique_ptr<IssuePolicy> make_issue_policy(const AcceleratorConfig& config) {
  const IssuePolicies::Entry* e = IssuePolicies::find(config.be.issue_policy);
  if (!e) throw std::invalid_argument("no issue policy '" + config.be.issue_policy + "' in this build");
  return e->make(config);
}

}  // namespace tigris::hw
