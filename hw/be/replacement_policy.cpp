#include "hw/be/replacement_policy.hpp"

namespace tigris::hw {

std::unique_ptr<ReplacementPolicy> make_replacement_policy(ReplacementPolicyKind kind) {
  if (kind == ReplacementPolicyKind::Fifo) return make_fifo_replacement();
  return make_lru_replacement();
}

}  // namespace tigris::hw
