// Largest first: evicts the biggest Node Set, so one eviction frees the most room and the many
// small sets stay; among sets of one size, the least recently used. Uses the sizes the Node
// Cache reports at each fill.
#include <unordered_map>

#include "hw/be/replacement_policy.hpp"

namespace tigris::hw {
namespace {

class LargestFirstReplacement final : public ReplacementPolicy {
 public:
  void reset() override { sets_.clear(), tick_ = 0; }
  void inserted(std::uint32_t leaf, std::uint64_t bytes) override { sets_[leaf] = {bytes, ++tick_}; }
  void hit(std::uint32_t leaf) override { sets_.at(leaf).used = ++tick_; }
  std::uint32_t evict() override {
    auto victim = sets_.begin();  // a scan: the cache holds tens of Node Sets
    for (auto it = sets_.begin(); it != sets_.end(); ++it)
      if (it->second.bytes > victim->second.bytes ||
          (it->second.bytes == victim->second.bytes && it->second.used < victim->second.used))
        victim = it;
    const std::uint32_t leaf = victim->first;
    sets_.erase(victim);
    return leaf;
  }

 private:
  struct Set {
    std::uint64_t bytes, used;  // size, and the tick of its last fill or read
  };
  std::unordered_map<std::uint32_t, Set> sets_;
  std::uint64_t tick_ = 0;
};

const bool registered =
    ReplacementPolicies::add("largest_first", "the biggest Node Set; least recently used among equals",
                             [](const AcceleratorConfig&) { return std::make_unique<LargestFirstReplacement>(); });

}  // namespace
}  // namespace tigris::hw
