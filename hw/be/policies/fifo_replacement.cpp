// First in, first out: Node Sets leave in the order they were filled; hits do not reorder them.
#include <deque>

#include "hw/be/replacement_policy.hpp"

namespace tigris::hw {
namespace {

class FifoReplacement final : public ReplacementPolicy {
 public:
  void reset() override { order_.clear(); }
  void inserted(std::uint32_t leaf, std::uint64_t) override { order_.push_back(leaf); }
  void hit(std::uint32_t) override {}
  std::uint32_t evict() override {
    const std::uint32_t victim = order_.front();
    order_.pop_front();
    return victim;
  }

 private:
  std::deque<std::uint32_t> order_;  // oldest fill first
};

const bool registered =
    ReplacementPolicies::add("fifo", "oldest filled; hits do not count",
                             [](const AcceleratorConfig&) { return std::make_unique<FifoReplacement>(); });

}  // namespace
}  // namespace tigris::hw
