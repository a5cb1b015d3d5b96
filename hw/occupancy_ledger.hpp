// A unit's cycles, each counted once. When a Search Unit runs several batches at a time (MQMN),
// their busy and stall intervals overlap; counted per batch they add up to more cycles than the
// unit has. Here a cycle is counted under the first state, in priority order, that any of the
// unit's intervals covering it is in (busy before any stall), so busy + stalls <= cycles. A
// unit books an interval no later than the cycle it begins at, so the cycles before `now` are
// final when settled; one batch at a time (MQSN) counts exactly as summing the intervals.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "stats.hpp"

namespace tigris::hw {

class OccupancyLedger {
 public:
  // One counter per state, highest priority first.
  explicit OccupancyLedger(std::vector<Counter*> by_priority) : counters_(std::move(by_priority)) {}

  void start(std::uint64_t now) { open_.clear(), settled_ = now; }
  // [begin, end) in `state`; begin must not lie before the last settle.
  void book(std::size_t state, std::uint64_t begin, std::uint64_t end) {
    if (end > begin) open_.push_back({begin, end, state});
  }
  // Counts [settled, now) and forgets the intervals that have ended by `now`.
  void settle(std::uint64_t now) {
    if (now <= settled_) return;
    if (disjoint()) {  // one batch at a time (MQSN): no cycle is claimed twice
      for (const Interval& i : open_) {
        const std::uint64_t b = std::max(i.begin, settled_), e = std::min(i.end, now);
        if (b < e) *counters_[i.state] += e - b;
      }
      forget(now);
      return;
    }
    events_.clear();
    for (const Interval& i : open_) {
      const std::uint64_t b = std::max(i.begin, settled_), e = std::min(i.end, now);
      if (b < e) events_.push_back({b, i.state, +1}), events_.push_back({e, i.state, -1});
    }
    std::sort(events_.begin(), events_.end(), [](const Event& x, const Event& y) { return x.at < y.at; });
    active_.assign(counters_.size(), 0);
    for (std::size_t k = 0; k < events_.size();) {
      const std::uint64_t at = events_[k].at;
      for (; k < events_.size() && events_[k].at == at; ++k) active_[events_[k].state] += events_[k].delta;
      if (k == events_.size()) break;
      for (std::size_t s = 0; s < active_.size(); ++s)
        if (active_[s] > 0) {
          *counters_[s] += events_[k].at - at;
          break;
        }
    }
    forget(now);
  }
  bool idle() const { return open_.empty(); }

 private:
  // At most two open intervals that do not overlap: the common case, counted without a sweep.
  bool disjoint() const {
    return open_.size() < 2 ||
           (open_.size() == 2 && (open_[0].end <= open_[1].begin || open_[1].end <= open_[0].begin));
  }
  void forget(std::uint64_t now) {
    open_.erase(std::remove_if(open_.begin(), open_.end(), [now](const Interval& i) { return i.end <= now; }),
                open_.end());
    settled_ = now;
  }
  struct Interval {
    std::uint64_t begin, end;
    std::size_t state;
  };
  struct Event {
    std::uint64_t at;
    std::size_t state;
    int delta;
  };
  std::vector<Counter*> counters_;
  std::vector<Interval> open_;
  std::vector<Event> events_;
  std::vector<int> active_;
  std::uint64_t settled_ = 0;
};

}  // namespace tigris::hw
