// The Search Unit's query issue logic (paper section 5.3), behind one small interface so the
// policies are interchangeable, one self-registering file each in hw/be/policies/
// (policy_registry.hpp): MQSN (all PEs scan one Node Set, found by an associative search of the
// BE Query Buffer), MQMN (any query to any free PE, each streaming its own Node Set), ...
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "hw/config.hpp"
#include "hw/job.hpp"
#include "hw/policy_registry.hpp"

namespace tigris::hw {

// The Node Cache as the issue logic sees it: which Node Sets it holds, read-only (NodeCache
// implements it; a policy file needs no SystemC).
class NodeCacheView {
 public:
  virtual bool resident(std::uint32_t leaf) const = 0;

 protected:
  ~NodeCacheView() = default;
};

struct IssueDecision {
  // The batches to start now, one after another in `positions`: each a list of BE Query Buffer
  // positions (ascending) whose queries stream one Node Set past their PEs together; batch b
  // ends before positions[ends[b]]. No position is in two batches. (Flat, so that the Search
  // Unit reuses one decision's storage.)
  std::vector<std::size_t> positions, ends;
  std::uint64_t search_cycles = 0;  // the associative search before the batches can start

  std::size_t batches() const { return ends.size(); }
  void clear() { positions.clear(), ends.clear(), search_cycles = 0; }
  void end_batch() { ends.push_back(positions.size()); }
};

// What the issue logic of one Search Unit sees when it picks: its BE Query Buffer (entries
// arrive in order; those with ready > now are still on their way), its PEs, the cycle, and
// which Node Sets the (shared) Node Cache holds, read-only.
struct IssueView {
  const std::vector<QueryToken>& bqb;
  std::uint32_t free_pes, pes;
  std::uint64_t now;
  const NodeCacheView& cache;
};

// One instance per Search Unit, so a policy may keep its own state (ages, round-robin
// pointers); start() begins each job. Every batch must hold queries of one leaf: the Search
// Unit checks it.
class IssuePolicy {
 public:
  virtual ~IssuePolicy() = default;
  virtual void start() {}
  // Chooses among the arrived entries, given the free PEs, into `d` (cleared first).
  virtual void pick(const IssueView& view, IssueDecision& d) = 0;
};

std::unique_ptr<IssuePolicy> make_issue_policy(const AcceleratorConfig& config);

}  // namespace tigris::hw
