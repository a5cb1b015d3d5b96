// The Search Unit's query issue logic (paper section 5.3), behind one small interface so the
// policies are interchangeable: MQSN (all PEs scan one Node Set; an associative search of the
// BE Query Buffer finds queries of the head's leaf) and MQMN (any query to any PE).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hw/config.hpp"
#include "hw/job.hpp"

namespace tigris::hw {

struct IssueDecision {
  std::vector<std::size_t> picks;  // positions in the BE Query Buffer, ascending
  std::uint64_t search_cycles = 0; // associative search before the batch can start
};

class IssuePolicy {
 public:
  virtual ~IssuePolicy() = default;
  // True when the whole PE array streams one Node Set (MQSN): issue waits for a free array.
  virtual bool shared_stream() const = 0;
  // Chooses queries among the buffer's entries that have arrived by `now`.
  virtual IssueDecision pick(const std::vector<QueryToken>& bqb, std::uint32_t free_pes,
                             std::uint64_t now) const = 0;
};

std::unique_ptr<IssuePolicy> make_issue_policy(const AcceleratorConfig& config);

}  // namespace tigris::hw
