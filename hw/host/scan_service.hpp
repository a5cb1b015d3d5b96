// The one seam between the model and the host's speed-ups, none of which is hardware: the PEs'
// exact NN/kNN scans (inline, or on a second host thread), the leaf sets' bounding boxes that
// let a fruitless scan be skipped, and the host cache hints. The units call this and nothing
// else of hw/host/: fe/ and be/ know nothing of threads, boxes or prefetch instructions, and the
// observers (hw/observer.hpp) see hardware events only.
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

#include "hw/job.hpp"
#include "hw/tree_view.hpp"
#include "leaf_bounds.hpp"
#include "prefetch.hpp"

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
    r2_ = job.r2;
    begin(job.slots);
  }

  // PE array `pe` scans `count` entries at `set`, all of leaf `leaf`'s Node Set or of its
  // leaders' lists, for `token`'s NN/kNN result slot: now or later, under the contract above.
  virtual void scan(PeArray& pe, const QueryToken& token, std::uint32_t leaf, const tlm_if::PointEntry* set,
                    std::uint32_t count) = 0;
  // The same for a scan whose results the Search Unit reads at once (radius hits, approximate
  // search): it runs now, into `hits` for radius.
  void scan_now(PeArray& pe, const QueryToken& token, std::uint32_t leaf, const tlm_if::PointEntry* set,
                std::uint32_t count, std::vector<tlm_if::ResultRecord>& hits);
  // Returns once every scan submitted for `slot` has written it.
  virtual void ready(std::uint32_t slot) = 0;
  // Returns once every scan submitted so far is done (no scan may outlive its Search Unit).
  virtual void drain() = 0;

  // Cache hints: host memory the model will read or write soon (no hardware event).
  static void read_soon(const void* p, std::size_t bytes) { prefetch_span(p, bytes); }
  static void write_soon(const void* p, std::size_t bytes) { prefetch_span_to_write(p, bytes); }
  void attach(QueryHint& hint) { hints_.push_back(&hint); }
  // `token`'s next walk is a few FQQ dispatches away: what ready() reads, and the hints.
  virtual void walk_soon(const QueryToken& token) { hint(token.query); }
  // `token` entered the BE Query Buffer of the Search Unit whose PEs are `pe`: what its scan
  // will touch, and the hints.
  virtual void queued(const PeArray& pe, const QueryToken& token) = 0;

 protected:
  virtual void begin(std::uint32_t slots) = 0;
  bool radius() const { return radius_; }
  const LeafBounds::Box& box(std::uint32_t leaf) const { return bounds_.box(leaf); }
  // Whether `leaf`'s box proves a scan for `token` changes nothing: every distance beyond the
  // radius, or beyond the slot's bound read now (a deferred scan asks when it runs).
  bool fruitless(const PeArray& pe, const QueryToken& token, const LeafBounds::Box& box) const;
  void hint(std::uint32_t query) const {
    for (QueryHint* h : hints_) h->soon(query);
  }

 private:
  LeafBounds bounds_;
  std::vector<QueryHint*> hints_;
  bool radius_ = false;
  float r2_ = 0.0f;
};

// `threaded` false: every scan runs inline in scan() (hw/host/inline_scans.hpp); true: on a
// second host thread (hw/host/threaded_scans.hpp). The figures are the same either way.
std::unique_ptr<ScanService> make_scan_service(bool threaded);

}  // namespace tigris::hw
