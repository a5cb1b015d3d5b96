#include "hw/be/mqmn_policy.hpp"

namespace tigris::hw {

void MqmnPolicy::pick(const IssueView& v, IssueDecision& d) {
  d.clear();
  for (std::size_t i = 0; i < v.bqb.size() && d.batches() < v.free_pes && v.bqb[i].ready <= v.now; ++i) {
    d.positions.push_back(i);
    d.end_batch();
  }
}

}  // namespace tigris::hw
