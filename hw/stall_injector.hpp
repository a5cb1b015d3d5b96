// Random hand-off stalls (MatchLib style; docs/model.md): with probability `stall.rate`
// a hand-off is held back one cycle, and again with the same probability for every further
// cycle (a geometric delay, mean rate / (1 - rate), at most 64). Results must not change, only
// cycles. Each injection point draws from its own stream: `stall.seed` mixed with the point's
// name inside the accelerator ("ru3", "points", ...), restarted at every START, so a job run
// twice, or beside another accelerator, draws the same delays.
#pragma once

#include <cstdint>
#include <string>

#include "config.hpp"
#include "stats.hpp"

namespace tigris::hw {

class StallInjector {
 public:
  // Counts the injected cycles as `stall_cycles.injected` in `group`.
  StallInjector(const AcceleratorConfig::Stall& config, const std::string& point, StatGroup& group)
      : rate_(config.rate), seed_(mix(config.seed ^ hash(point))), state_(seed_),
        injected_(group, "stall_cycles.injected", "cycles",
                  "random stall cycles injected at this block's hand-off (`stall.rate`; 0 when off)") {}

  void start() { state_ = seed_; }
  // Cycles to hold the current hand-off back (0 unless stalls are on).
  std::uint64_t draw() {
    if (rate_ <= 0.0) return 0;
    std::uint64_t d = 0;
    while (d < 64 && uniform() < rate_) ++d;
    injected_ += d;
    return d;
  }

 private:
  static std::uint64_t hash(const std::string& s) {  // FNV-1a
    std::uint64_t h = 1469598103934665603ull;
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    return h;
  }
  static std::uint64_t mix(std::uint64_t x) {  // splitmix64's finaliser
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
  }
  double uniform() {  // splitmix64 step, 53 bits
    state_ += 0x9e3779b97f4a7c15ull;
    return static_cast<double>(mix(state_) >> 11) * (1.0 / 9007199254740992.0);
  }

  double rate_;
  std::uint64_t seed_, state_;
  Counter injected_;
};

}  // namespace tigris::hw
