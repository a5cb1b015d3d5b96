#include "hw/be/mqsn_policy.hpp"

namespace tigris::hw {

void MqsnPolicy::pick(const IssueView& v, IssueDecision& d) {
  d.clear();
  const std::vector<QueryToken>& bqb = v.bqb;
  const std::uint32_t free_pes = v.free_pes;
  const std::uint64_t now = v.now;
  if (free_pes < v.pes || bqb.empty() || bqb.front().ready > now) return;
  const std::uint32_t key = bqb.front().leaf;
  std::size_t scanned = 0;
  for (std::size_t i = 0; i < bqb.size() && d.positions.size() < free_pes; ++i) {
    if (bqb[i].ready > now) break;  // entries arrive in order; later ones are not here yet
    scanned = i + 1;
    if (bqb[i].leaf == key) d.positions.push_back(i);
  }
  d.search_cycles = (scanned + width_ - 1) / width_;
  d.end_batch();
}

}  // namespace tigris::hw
