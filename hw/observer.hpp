// What the units report as they search, for whoever attaches (after Ramulator 2's plug-ins):
// the testbench's scoreboard records per-query visit counts and the leaf-visit schedule through
// it. The units keep no per-query state of their own for this.
#pragma once

#include <cstdint>
#include <vector>

namespace tigris::hw {

class JobObserver {
 public:
  virtual ~JobObserver() = default;
  virtual void job_started(std::uint32_t /*num_queries*/) {}
  // A Recursion Unit activation of `query`: `top` nodes compared, `pruned` subtrees skipped.
  virtual void walked(std::uint32_t /*query*/, std::uint32_t /*top*/, std::uint32_t /*pruned*/) {}
  // A leaf-visit decision, in simulated-time order: `query` scans `points` entries of `leaf`.
  virtual void leaf_scanned(std::uint32_t /*query*/, std::uint32_t /*leaf*/, std::uint32_t /*points*/) {}
};

// Forwards every report to the attached observers.
class ObserverList final : public JobObserver {
 public:
  void attach(JobObserver& o) { list_.push_back(&o); }
  void job_started(std::uint32_t n) override {
    for (JobObserver* o : list_) o->job_started(n);
  }
  void walked(std::uint32_t q, std::uint32_t top, std::uint32_t pruned) override {
    for (JobObserver* o : list_) o->walked(q, top, pruned);
  }
  void leaf_scanned(std::uint32_t q, std::uint32_t leaf, std::uint32_t points) override {
    for (JobObserver* o : list_) o->leaf_scanned(q, leaf, points);
  }

 private:
  std::vector<JobObserver*> list_;
};

}  // namespace tigris::hw
