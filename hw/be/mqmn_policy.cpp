#include "hw/be/mqmn_policy.hpp"

namespace tigris::hw {

void MqmnPolicy::pick(const std::vector<QueryToken>& bqb, std::uint32_t free_pes, std::uint32_t /*pes*/,
                      std::uint64_t now, IssueDecision& d) const {
  d.clear();
  for (std::size_t i = 0; i < bqb.size() && d.batches() < free_pes && bqb[i].ready <= now; ++i) {
    d.positions.push_back(i);
    d.end_batch();
  }
}

}  // namespace tigris::hw
