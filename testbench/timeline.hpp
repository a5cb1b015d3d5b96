// `tigris run --timeline FILE` (docs/cli.md): the run as a Chrome trace-event JSON that
// Perfetto (ui.perfetto.dev) and chrome://tracing open. One process per block: the front-end
// with a track per RU (a slice per walk, per BQB-full hold), the QDN with a track per SU port
// (a slice per hop), the back-end with tracks per SU lane (a slice per batch: leaf, queries,
// stream length; overlapping MQMN batches take further lanes) and the BQB waits as async slices
// per SU, and the write-back (a slice per accepted chunk until it is in DRAM). Flow arrows
// follow each query from hop to hop. Only sampled queries appear on those tracks (every
// `stride`-th, so that about `max_queries` do; the track names say so): a batch shows when one
// of its queries is sampled. A "Whole machine" process adds counters over every query, whatever
// the sampling: RUs busy and stalled by cause, PEs busy, waiting for data and held by the
// write-back, BQB occupancy and the write-back backlog, each the exact mean over bins of the run
// (about kCounterBins of them).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hw/observer.hpp"

namespace tigris {

class TimelineRecorder final : public hw::JobObserver {
 public:
  // `period_ns`: one cycle in nanoseconds (trace timestamps are in microseconds).
  TimelineRecorder(double period_ns, std::uint32_t max_queries) : period_ns_(period_ns), max_queries_(max_queries) {}

  void job_started(std::uint32_t num_queries) override;
  void ru_walk(std::uint32_t ru, std::uint32_t query, std::uint64_t begin, std::uint64_t end) override;
  void ru_blocked(std::uint32_t ru, std::uint32_t query, std::uint64_t begin, std::uint64_t end) override;
  void qdn_hop(std::uint32_t su, std::uint32_t query, std::uint64_t send, std::uint64_t arrive) override;
  void su_batch(std::uint32_t su, std::uint32_t leaf, const hw::QueryToken* tokens, std::size_t n, std::uint64_t issue,
                std::uint64_t end, std::uint64_t stream) override;
  void writeback(std::uint32_t query, std::size_t records, std::uint64_t accept, std::uint64_t drained) override;
  void activity(Activity what, std::uint32_t count, std::uint64_t begin, std::uint64_t end) override;

  static constexpr std::uint64_t kCounterBins = 2000;
  // Every how-many-th query the slices show, for about `max_queries` of `num_queries`.
  static std::uint32_t stride_for(std::uint32_t num_queries, std::uint32_t max_queries) {
    const std::uint32_t m = max_queries > 0 ? max_queries : 1;
    const std::uint32_t ceil = num_queries / m + (num_queries % m != 0 ? 1 : 0);  // no overflow near 2^32
    return ceil > 0 ? ceil : 1;
  }
  static constexpr double kBytesPerVisit = 1000.0;  // calibrated in timeline.cpp's estimate
  // About how many bytes of JSON a timeline of `queries` sampled queries takes, from the
  // estimated leaf visits per query (measured: ~1 KB per sampled leaf visit, whatever the cloud).
  static double estimated_bytes(double queries, double leaf_visits_per_query);

  // The trace: {"traceEvents": [...], "displayTimeUnit": "ns", "otherData": {...}}.
  nlohmann::json trace() const;
  std::uint32_t stride() const { return stride_; }
  std::string trace_note() const { return sampled_note(); }

 private:
  enum Pid { kMachine = 0, kFrontEnd = 1, kQdn = 2, kBackEnd = 3, kWriteback = 4 };
  // Counter series: the Activity values, then BQB occupancy and write-back backlog (records).
  static constexpr int kBqb = 7, kBacklog = 8, kSeries = 9;
  void count(int series, std::uint64_t begin, std::uint64_t end, std::int64_t n);
  void add_counters(nlohmann::json& events) const;
  std::string sampled_note() const;
  bool sampled(std::uint32_t query) const { return query % stride_ == 0; }
  double us(std::uint64_t cycle) const { return static_cast<double>(cycle) * period_ns_ / 1000.0; }
  void slice(int pid, std::uint64_t tid, const std::string& name, std::uint64_t begin, std::uint64_t end,
             nlohmann::json args);
  // A flow arrow from the query's previous slice to the one starting at `begin` on (pid, tid).
  void hop(std::uint32_t query, int pid, std::uint64_t tid, std::uint64_t begin);
  void name_track(int pid, std::uint64_t tid, const std::string& name);

  double period_ns_;
  std::uint32_t max_queries_;
  std::uint32_t stride_ = 1;
  nlohmann::json events_ = nlohmann::json::array();
  struct Last {  // where a query's last slice ended, for its next flow arrow
    int pid = 0;
    std::uint64_t tid = 0, end = 0;
    bool any = false;
  };
  std::vector<Last> last_;
  std::vector<std::vector<std::uint64_t>> lanes_;  // per SU: each lane's busy-until cycle
  std::vector<std::uint64_t> writeback_lanes_;
  std::vector<std::vector<std::uint64_t>> qdn_lanes_;
  std::vector<bool> named_;  // tracks named so far (by a packed key)
  std::uint64_t flow_id_ = 0;
  // Per series: (cycle, change) of its level, over every query.
  std::vector<std::pair<std::uint64_t, std::int64_t>> deltas_[kSeries];
};

}  // namespace tigris
