// What the units report as they search, for whoever attaches (after Ramulator 2's plug-ins):
// the testbench's scoreboard records per-query visit counts and the leaf-visit schedule through
// it. The units keep no per-query state of their own for this.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "job.hpp"

namespace tigris::hw {

// How a query was served at one leaf visit (docs/model.md, approximate search).
struct LeafVisit {
  enum class Kind {
    Exact,             // exact search: the Node Set
    Leader,            // approximate: no leader close enough; scanned the Node Set, joined
    LeaderBufferFull,  // approximate: as Leader, but the leaf's Leader Buffer was full
    Follower,          // approximate: scanned its closest leader's (local or final) result list
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
  // first_leaf: the record of `query`, a finished leader of `leaf`, reached the leaf's Leader
  // Buffer, which took it (`joined`) or was full; in simulated-time order with the visits.
  virtual void leader_finished(std::uint32_t /*query*/, std::uint32_t /*leaf*/, bool /*joined*/) {}
  // first_leaf, wait: `query`, a follower whose leader was still searching at its check, has
  // now scanned that leader's list of `points` entries (its visit was reported at the check).
  virtual void follower_served(std::uint32_t /*query*/, std::uint32_t /*points*/) {}
  // `query` took a Query Stack slot (admission) / its last results entered the write-back
  // stream (finished), at `cycle`; it waited `cycles` in a BE Query Buffer before its batch.
  virtual void query_admitted(std::uint32_t /*query*/, std::uint64_t /*cycle*/) {}
  virtual void query_finished(std::uint32_t /*query*/, std::uint64_t /*cycle*/) {}
  virtual void bqb_waited(std::uint32_t /*query*/, std::uint64_t /*cycles*/) {}

  // When work happens (absolute cycles), for timelines:
  // an RU walk of `query` (an activation, up to its CL stage);
  virtual void ru_walk(std::uint32_t /*ru*/, std::uint32_t /*query*/, std::uint64_t /*begin*/, std::uint64_t /*end*/) {}
  // an RU holding `query` while the target BE Query Buffer is full;
  virtual void ru_blocked(std::uint32_t /*ru*/, std::uint32_t /*query*/, std::uint64_t /*begin*/,
                          std::uint64_t /*end*/) {}
  // `query` sent over the QDN port of SU `su` at `send`, in its BE Query Buffer at `arrive`;
  virtual void qdn_hop(std::uint32_t /*su*/, std::uint32_t /*query*/, std::uint64_t /*send*/,
                       std::uint64_t /*arrive*/) {}
  // a Search Unit batch at `leaf`: `n` queries (each token's `ready` is its BQB arrival),
  // issued at `issue`, streaming `stream` entries until `end`;
  virtual void su_batch(std::uint32_t /*su*/, std::uint32_t /*leaf*/, const QueryToken* /*tokens*/, std::size_t /*n*/,
                        std::uint64_t /*issue*/, std::uint64_t /*end*/, std::uint64_t /*stream*/) {}
  // `records` result records of `query` accepted by the write-back at `accept`, in DRAM by `drained`.
  virtual void writeback(std::uint32_t /*query*/, std::size_t /*records*/, std::uint64_t /*accept*/,
                         std::uint64_t /*drained*/) {}
  // `count` units (RUs or PEs) spend [begin, end) in state `what`: the same cycles the
  // statistics count, for whole-machine counters whatever a timeline samples.
  enum class Activity { RuBusy, RuSramStall, RuBqbFull, RuWritebackStall, PeBusy, PeSramStall, PeWritebackHold };
  virtual void activity(Activity /*what*/, std::uint32_t /*count*/, std::uint64_t /*begin*/, std::uint64_t /*end*/) {}
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
  void leader_finished(std::uint32_t q, std::uint32_t leaf, bool joined) override {
    for (JobObserver* o : list_) o->leader_finished(q, leaf, joined);
  }
  void follower_served(std::uint32_t q, std::uint32_t points) override {
    for (JobObserver* o : list_) o->follower_served(q, points);
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
  void ru_walk(std::uint32_t ru, std::uint32_t q, std::uint64_t b, std::uint64_t e) override {
    for (JobObserver* o : list_) o->ru_walk(ru, q, b, e);
  }
  void ru_blocked(std::uint32_t ru, std::uint32_t q, std::uint64_t b, std::uint64_t e) override {
    for (JobObserver* o : list_) o->ru_blocked(ru, q, b, e);
  }
  void qdn_hop(std::uint32_t su, std::uint32_t q, std::uint64_t send, std::uint64_t arrive) override {
    for (JobObserver* o : list_) o->qdn_hop(su, q, send, arrive);
  }
  void su_batch(std::uint32_t su, std::uint32_t leaf, const QueryToken* t, std::size_t n, std::uint64_t issue,
                std::uint64_t end, std::uint64_t stream) override {
    for (JobObserver* o : list_) o->su_batch(su, leaf, t, n, issue, end, stream);
  }
  void activity(Activity what, std::uint32_t count, std::uint64_t begin, std::uint64_t end) override {
    for (JobObserver* o : list_) o->activity(what, count, begin, end);
  }
  void writeback(std::uint32_t q, std::size_t records, std::uint64_t accept, std::uint64_t drained) override {
    for (JobObserver* o : list_) o->writeback(q, records, accept, drained);
  }

 private:
  std::vector<JobObserver*> list_;
};

}  // namespace tigris::hw
