// Which Node Set the Node Cache evicts: one small interface, one file per policy
// (lru_replacement.cpp, fifo_replacement.cpp); node_cache.policy chooses.
#pragma once

#include <cstdint>
#include <memory>

#include "hw/config.hpp"

namespace tigris::hw {

class ReplacementPolicy {
 public:
  virtual ~ReplacementPolicy() = default;
  virtual void reset() = 0;
  virtual void inserted(std::uint32_t leaf, std::uint64_t bytes) = 0;  // a Node Set of `bytes` was filled
  virtual void hit(std::uint32_t leaf) = 0;       // a cached Node Set was read
  virtual std::uint32_t evict() = 0;              // chooses and forgets a victim (cache not empty)
};

std::unique_ptr<ReplacementPolicy> make_lru_replacement();
std::unique_ptr<ReplacementPolicy> make_fifo_replacement();
// The policy node_cache.policy names.
std::unique_ptr<ReplacementPolicy> make_replacement_policy(ReplacementPolicyKind kind);

}  // namespace tigris::hw
