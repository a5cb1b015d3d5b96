#include "hw/be/mqsn_policy.hpp"

namespace tigris::hw {

IssueDecision MqsnPolicy::pick(const std::vector<QueryToken>& bqb, std::uint32_t free_pes,
                               std::uint32_t pes, std::uint64_t now) const {
  IssueDecision d;
  if (free_pes < pes || bqb.empty() || bqb.front().ready > now) return d;
  const std::uint32_t key = bqb.front().leaf;
  std::vector<std::size_t> batch;
  std::size_t scanned = 0;
  for (std::size_t i = 0; i < bqb.size() && batch.size() < free_pes; ++i) {
    if (bqb[i].ready > now) break;  // entries arrive in order; later ones are not here yet
    scanned = i + 1;
    if (bqb[i].leaf == key) batch.push_back(i);
  }
  d.search_cycles = (scanned + width_ - 1) / width_;
  d.batches.push_back(std::move(batch));
  return d;
}

}  // namespace tigris::hw
