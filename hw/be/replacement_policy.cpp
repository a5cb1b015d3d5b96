#include "replacement_policy.hpp"

#include <stdexcept>

namespace tigris::hw {

std::unique_ptr<ReplacementPolicy> make_replacement_policy(const AcceleratorConfig& config) {
  const ReplacementPolicies::Entry* e = ReplacementPolicies::find(config.node_cache.policy);
  if (!e) throw std::invalid_argument("no replacement policy '" + config.node_cache.policy + "' in this build");
  return e->make(config);
}

}  // namespace tigris::hw
