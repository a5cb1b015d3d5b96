// Cache first: MQSN (one Node Set at a time, every PE free, an associative search) whose key is
// the first arrived entry whose Node Set the Node Cache holds, so a batch streams from the cache
// rather than the Point Buffer; without one, the head's leaf, as MQSN. Fairness: after four picks
// in a row that passed the head over, the head's leaf goes next (state of this SU's instance).
#include <algorithm>

#include "hw/be/issue_policy.hpp"

namespace tigris::hw {
namespace {

class CacheFirstIssue final : public IssuePolicy {
 public:
  explicit CacheFirstIssue(int search_width) : width_(static_cast<std::uint64_t>(search_width)) {}
  void start() override { passed_over_ = 0; }
  void pick(const IssueView& v, IssueDecision& d) override {
    d.clear();
    if (v.free_pes < v.pes || v.bqb.empty() || v.bqb.front().ready > v.now) return;
    // The key: the first arrived entry with a resident Node Set, looked for in the same pass.
    std::size_t arrived = 0, key_at = 0;
    bool found = passed_over_ >= kMaxPassedOver;  // the head's turn
    for (; arrived < v.bqb.size() && v.bqb[arrived].ready <= v.now; ++arrived)
      if (!found && v.cache.resident(v.bqb[arrived].leaf)) key_at = arrived, found = true;
    const std::uint32_t key = v.bqb[key_at].leaf;
    passed_over_ = key_at == 0 || v.bqb.front().leaf == key ? 0 : passed_over_ + 1;
    std::size_t scanned = 0;
    for (std::size_t i = 0; i < arrived && d.positions.size() < v.free_pes; ++i) {
      scanned = i + 1;
      if (v.bqb[i].leaf == key) d.positions.push_back(i);
    }
    // The associative search compares `width` entries a cycle, as far as the key and the batch reach.
    d.search_cycles = (std::max(scanned, key_at + 1) + width_ - 1) / width_;
    d.end_batch();
  }

 private:
  static constexpr int kMaxPassedOver = 4;
  std::uint64_t width_;
  int passed_over_ = 0;
};

const bool registered = IssuePolicies::add(
    "cache_first",
    "as mqsn, but the key is the first arrived query whose Node Set is in the Node Cache; the head's "
    "after four picks that passed it over",
    [](const AcceleratorConfig& c) { return std::make_unique<CacheFirstIssue>(c.be.issue_search_width); });

}  // namespace
}  // namespace tigris::hw
