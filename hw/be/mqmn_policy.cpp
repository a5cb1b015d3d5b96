#include "hw/be/mqmn_policy.hpp"

namespace tigris::hw {

IssueDecision MqmnPolicy::pick(const std::vector<QueryToken>& bqb, std::uint32_t free_pes,
                               std::uint32_t /*pes*/, std::uint64_t now) const {
  IssueDecision d;
  for (std::size_t i = 0; i < bqb.size() && d.batches.size() < free_pes && bqb[i].ready <= now; ++i)
    d.batches.push_back({i});
  return d;
}

}  // namespace tigris::hw
