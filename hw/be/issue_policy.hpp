// The Search Unit's query issue logic (paper section 5.3), behind one small interface so the
// policies are interchangeable, one file each: MQSN (mqsn_policy.cpp: all PEs scan one Node
// Set, found by an associative search of the BE Query Buffer) and MQMN (mqmn_policy.cpp: any
// query to any free PE, each streaming its own Node Set).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "hw/config.hpp"
#include "hw/job.hpp"

namespace tigris::hw {

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

class IssuePolicy {
 public:
  virtual ~IssuePolicy() = default;
  // Chooses among the buffer's entries that have arrived by `now`, given `free_pes` of `pes`,
  // into `d` (cleared first).
  virtual void pick(const std::vector<QueryToken>& bqb, std::uint32_t free_pes, std::uint32_t pes,
                    std::uint64_t now, IssueDecision& d) const = 0;
};

std::unique_ptr<IssuePolicy> make_issue_policy(const AcceleratorConfig& config);

}  // namespace tigris::hw
