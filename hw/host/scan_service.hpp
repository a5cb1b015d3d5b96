// The one seam between the model and the host's speed-ups, none of which is hardware: the PEs'
// exact NN/kNN scans (inline, or on a second host thread), the leaf sets' bounding boxes that
// let a fruitless scan be skipped, and the prefetch hints. The units call this; fe/ and be/
// know nothing of threads, and the observers (hw/observer.hpp) see hardware events only.
//
// The deferred-result contract. An NN/kNN scan's results never feed the timing: a batch's cycles
// come from its Node Set's size, and the only reader of a query's result slot is that query's
// next Recursion Unit walk, thousands of cycles later. So scan() may return before the scan has
// run. ready(slot) returns once every scan of `slot` submitted so far has written it, and the RU
// calls it before it reads the slot. A slot's scans run in submission order, so the results are
// bit for bit those of inline scans. Radius hits and approximate search (whose Leader Buffer
// decisions the timing reads at once) do not come here: the Search Unit scans them inline.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "hw/host/leaf_bounds.hpp"
#include "hw/job.hpp"
#include "hw/tree_view.hpp"

namespace tigris::hw {

class PeArray;  // hw/be/pe_array.hpp

// Whoever keeps per-query records on the host (the testbench's scoreboard) may start loading
// `query`'s record into the cache when the units are about to report on it.
class QueryHint {
 public:
  virtual ~QueryHint() = default;
  virtual void soon(std::uint32_t query) = 0;
};

class ScanService {
 public:
  virtual ~ScanService() = default;

  // A job starts: the boxes of the leaf sets now in the Point Buffer, the job's result slots.
  void start(const JobDescriptor& job, const TreeView& tree) {
    bounds_.build(tree, job.num_leaves);
    radius_ = job.radius();
    begin(job.slots);
  }
  // Holds every entry of `leaf`'s Node Set and of its leaders' lists (hw/host/leaf_bounds.hpp).
  const LeafBounds::Box& box(std::uint32_t leaf) const { return bounds_.box(leaf); }

  // PE array `pe` scans `count` entries at `set` (within `box`) for `token`'s NN/kNN result slot:
  // now or later, under the contract above.
  virtual void scan(PeArray& pe, const QueryToken& token, const tlm_if::PointEntry* set, std::uint32_t count,
                    const LeafBounds::Box* box) = 0;
  // Returns once every scan submitted for `slot` has written it.
  virtual void ready(std::uint32_t slot) = 0;
  // Returns once every scan submitted so far is done (no scan may outlive its Search Unit).
  virtual void drain() = 0;

  // Prefetch hints (host cache lines only, no hardware event).
  void attach(QueryHint& hint) { hints_.push_back(&hint); }
  // `token`'s next walk is a few FQQ dispatches away: what ready() reads, and the hints.
  virtual void walk_soon(const QueryToken& token) { hint(token.query); }
  // `token` entered the BE Query Buffer of the Search Unit whose PEs are `pe`: what its scan
  // will touch, and the hints.
  virtual void queued(const PeArray& pe, const QueryToken& token) = 0;

 protected:
  virtual void begin(std::uint32_t slots) = 0;
  bool radius() const { return radius_; }
  void hint(std::uint32_t query) const {
    for (QueryHint* h : hints_) h->soon(query);
  }

 private:
  LeafBounds bounds_;
  std::vector<QueryHint*> hints_;
  bool radius_ = false;
};

// `threaded` false: every scan runs inline in scan() (hw/host/inline_scans.hpp); true: on a
// second host thread (hw/host/threaded_scans.hpp). The figures are the same either way.
std::unique_ptr<ScanService> make_scan_service(bool threaded);

}  // namespace tigris::hw
