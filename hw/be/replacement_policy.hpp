// Which Node Set the Node Cache evicts: one small interface, one self-registering file per
// policy in hw/be/policies/ (policy_registry.hpp); node_cache.policy chooses by name.
#pragma once

#include <cstdint>
#include <memory>

#include "hw/config.hpp"
#include "hw/policy_registry.hpp"

namespace tigris::hw {

class ReplacementPolicy {
 public:
  virtual ~ReplacementPolicy() = default;
  virtual void reset() = 0;
  virtual void inserted(std::uint32_t leaf, std::uint64_t bytes) = 0;  // a Node Set of `bytes` was filled
  virtual void hit(std::uint32_t leaf) = 0;                            // a cached Node Set was read
  virtual std::uint32_t evict() = 0;                                   // chooses and forgets a victim (cache not empty)
};

// The policy node_cache.policy names.
std::unique_ptr<ReplacementPolicy> make_replacement_policy(const AcceleratorConfig& config);

}  // namespace tigris::hw
