// Least recently used: a list in recency order and an index into it.
#include <list>
#include <unordered_map>

#include "hw/be/replacement_policy.hpp"

namespace tigris::hw {
namespace {

class LruReplacement final : public ReplacementPolicy {
 public:
  void reset() override {
    order_.clear();
    where_.clear();
  }
  void inserted(std::uint32_t leaf, std::uint64_t) override {
    order_.push_front(leaf);
    where_[leaf] = order_.begin();
  }
  void hit(std::uint32_t leaf) override { order_.splice(order_.begin(), order_, where_.at(leaf)); }
  std::uint32_t evict() override {
    const std::uint32_t victim = order_.back();
    order_.pop_back();
    where_.erase(victim);
    return victim;
  }

 private:
  std::list<std::uint32_t> order_;  // most recent first
  std::unordered_map<std::uint32_t, std::list<std::uint32_t>::iterator> where_;
};

const bool registered = ReplacementPolicies::add("lru", "least recently read or filled", [](const AcceleratorConfig&) {
  return std::make_unique<LruReplacement>();
});

}  // namespace
}  // namespace tigris::hw
