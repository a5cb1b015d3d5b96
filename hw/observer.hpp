// What the units report as they search, for whoever attaches (after Ramulator 2's plug-ins):
// the testbench's scoreboard records per-query visit counts and the leaf-visit schedule through
// it. The units keep no per-query state of their own for this.
#pragma once

#include <cstdint>
#include <vector>

namespace tigris::hw {

// How a query was served at one leaf visit (DESIGN.md sections 5 and 13).
struct LeafVisit {
  enum class Kind {
    Exact,             // exact search: the Node Set
    Leader,            // approximate: no leader close enough; scanned the Node Set, joined
    LeaderBufferFull,  // approximate: as Leader, but the leaf's Leader Buffer was full
    Follower,          // approximate: scanned its closest leader's local result list
  };
  Kind kind = Kind::Exact;
  std::uint32_t leaf_points = 0;      // Node Set entries compared
  std::uint32_t follower_points = 0;  // leader-list entries compared
  std::uint32_t leader_checks = 0;    // distances to the leaf's leaders
};

class JobObserver {
 public:
  virtual ~JobObserver() = default;
  virtual void job_started(std::uint32_t /*num_queries*/) {}
  // A Recursion Unit activation of `query`: `top` nodes compared, `pruned` subtrees skipped.
  virtual void walked(std::uint32_t /*query*/, std::uint32_t /*top*/, std::uint32_t /*pruned*/) {}
  // A leaf-visit decision, in simulated-time order: how `query` is served at `leaf`.
  virtual void leaf_scanned(std::uint32_t /*query*/, std::uint32_t /*leaf*/, const LeafVisit& /*visit*/) {}
  // `query` took a Query Stack slot (admission) / its last results entered the write-back
  // stream (finished), at `cycle`; it waited `cycles` in a BE Query Buffer before its batch.
  virtual void query_admitted(std::uint32_t /*query*/, std::uint64_t /*cycle*/) {}
  virtual void query_finished(std::uint32_t /*query*/, std::uint64_t /*cycle*/) {}
  virtual void bqb_waited(std::uint32_t /*query*/, std::uint64_t /*cycles*/) {}
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
  void leaf_scanned(std::uint32_t q, std::uint32_t leaf, const LeafVisit& visit) override {
    for (JobObserver* o : list_) o->leaf_scanned(q, leaf, visit);
  }
  void query_admitted(std::uint32_t q, std::uint64_t cycle) override {
    for (JobObserver* o : list_) o->query_admitted(q, cycle);
  }
  void query_finished(std::uint32_t q, std::uint64_t cycle) override {
    for (JobObserver* o : list_) o->query_finished(q, cycle);
  }
  void bqb_waited(std::uint32_t q, std::uint64_t cycles) override {
    for (JobObserver* o : list_) o->bqb_waited(q, cycles);
  }

 private:
  std::vector<JobObserver*> list_;
};

}  // namespace tigris::hw
