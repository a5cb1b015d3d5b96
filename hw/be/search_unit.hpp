// Search Unit (paper section 5.3): BE Query Buffer, query issue logic, systolic PE array and
// the Node Set stream from the Point Buffer (or the Node Cache). A batch is one work item: its
// cycles are the stream formula, stretched by the buffers' bank contention.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include <systemc>

#include "hw/clock.hpp"
#include "hw/config.hpp"
#include "hw/energy_meter.hpp"
#include "hw/host/scan_service.hpp"
#include "hw/job.hpp"
#include "hw/mem/buffer_port.hpp"
#include "hw/observer.hpp"
#include "hw/occupancy_ledger.hpp"
#include "hw/probe.hpp"
#include "hw/scheduler.hpp"
#include "hw/stall_injector.hpp"
#include "hw/stats.hpp"
#include "issue_policy.hpp"
#include "leader_buffer.hpp"
#include "leader_check.hpp"
#include "node_cache.hpp"
#include "pe_array.hpp"

namespace tigris::hw {

class FrontEnd;
class DistributionNetwork;
class ResultBuffer;

class SearchUnit : public sc_core::sc_module, private Scheduler::Client {
 public:
  BufferPort points, results;

  // What a Search Unit works with: the blocks it hands queries and results to.
  struct Links {
    FrontEnd& fe;
    DistributionNetwork& qdn;
    NodeCache& cache;
    ResultBuffer& result_buffer;
    EnergyMeter& meter;
    JobObserver& observer;
    Scheduler& scheduler;
    ScanService& scans;  // the host's side of the NN/kNN scans (deferred results) and leaf boxes
  };
  SearchUnit(sc_core::sc_module_name name, std::uint32_t id, const AcceleratorConfig& config, const JobDescriptor& job,
             Links links);

  void start();  // a job starts: empty buffers, all PEs free, views onto the new job's data
  void finish() { ledger_.settle(clock_.now()); }  // the job has ended: its last cycles counted
  bool has_room() const { return bqb_.size() < capacity_; }
  std::size_t room() const { return capacity_ - bqb_.size(); }
  void accept(const QueryToken& token);  // from the QDN; the caller checked has_room()
  // first_leaf: a finished leader's record, applied at its `ready` cycle.
  void leader_arrives(LeaderRecord record);

  std::size_t bqb_occupancy() const { return bqb_.size(); }
  std::uint32_t busy_pes() const { return pes_ - free_pes_; }
  StatGroup& stats() { return stats_; }
  void attach_waves(VcdWriter& vcd, const std::string& scope, AggregateProbes& all) {
    bqb_wave_.feed(all.bqb_occupancy);
    pes_wave_.feed(all.busy_pes);
    sram_pes_wave_.feed(all.pes_sram_stall);
    writeback_pes_wave_.feed(all.pes_writeback_stall);
    bqb_wave_.attach(vcd, scope + ".bqb_occupancy", 16);
    pes_wave_.attach(vcd, scope + ".busy_pes", 16);
    sram_pes_wave_.attach(vcd, scope + ".sram_stall_pes", 16);
    writeback_pes_wave_.attach(vcd, scope + ".writeback_stall_pes", 16);
    leaf_wave_.attach(vcd, scope + ".streaming_leaf", 32);
  }

 private:
  struct Batch {
    std::vector<QueryToken> tokens;
    std::vector<tlm_if::ResultRecord> hits;  // radius hits, streamed out at the end
    std::uint64_t end = 0;
    bool written = false;  // results handed to the Result Buffer / write-back stream
  };
  void wake() override { step(); }
  void step();  // retire finished batches, issue new ones
  void issue(Batch& batch, std::uint64_t now, std::uint64_t setup);
  Batch& add_batch();  // a cleared batch at the end of the running ones (storage reused)
  // How a batch is served: its exact scans, the leaders it followed and the ones it appended.
  struct Plan {
    std::uint64_t exact = 0;                         // queries scanning the Node Set
    std::uint64_t max_checks = 0;                    // leaders the last Leader Check compared against
    std::vector<std::size_t> followed, new_leaders;  // leader indices at the batch's leaf
  };
  Plan serve(std::vector<QueryToken>& tokens, std::uint32_t leaf, std::uint64_t now,
             std::vector<tlm_if::ResultRecord>& hits);
  void exact_scan(const QueryToken& t, std::uint32_t leaf, const tlm_if::PointEntry* set, std::uint32_t n,
                  std::vector<tlm_if::ResultRecord>& hits);
  void apply_leader_records(std::uint64_t now);           // records that have arrived join (or find L full)
  void issue_followers(Batch& batch, std::uint64_t now);  // parked followers of one leader, now ready
  // The batch's stream from `start` (after its checks, at `check_end`), `stream` entries whose
  // last arrives at `data_ready`: its end, busy and stall cycles.
  void stream_batch(Batch& batch, std::uint32_t leaf, std::uint64_t now, std::uint64_t start, std::uint64_t check_end,
                    std::uint64_t data_ready, std::uint64_t stream);
  // A leader's list written (at its leader's scan end) or read, from cycle `at`; returns when done.
  std::uint64_t list_access(std::uint64_t at, const LeaderBuffer::Leader& l, bool write);
  std::uint64_t retire(Batch& batch);  // returns the cycle the queries may leave
  // The batch's NN/kNN slots in the Result Buffer, as one scattered access.
  tlm_if::AccessProfile slot_access(const std::vector<QueryToken>& tokens, bool write);

  std::uint32_t id_;
  const AcceleratorConfig& config_;
  const JobDescriptor& job_;
  Links links_;
  Clock clock_;
  std::size_t capacity_;
  std::uint32_t pes_, free_pes_;
  std::vector<QueryToken> bqb_;
  std::vector<Batch> running_;  // the first `active_` are streaming; the rest keep their storage
  std::size_t active_ = 0;
  std::unique_ptr<IssuePolicy> policy_;  // this SU's own (be.issue_policy)
  IssueDecision decision_;
  PeArray pe_array_;
  LeaderBuffer leader_buffer_;
  std::vector<tlm_if::PointEntry> local_;   // a new leader's local result list
  std::deque<LeaderRecord> arrivals_;       // first_leaf leaders' records on their way (ready order)
  std::deque<QueryToken> ready_followers_;  // wait: parked followers whose leader's list is written
  std::vector<char> taken_;                 // BQB positions issued this step
  TreeView tree_;
  std::vector<std::uint64_t> slot_addrs_;
  StatGroup stats_;
  Counter batches_{stats_, "batches", "count", "batches issued: Node Set (or leader-list) streams through a PE array"};
  Counter queries_{stats_, "queries", "count", "query-leaf visits served"};
  Counter busy_cycles_{stats_, "busy_cycles", "cycles",
                       "cycles with the PE array streaming (fill, stream, drain; overlapping MQMN batches count once)"};
  // A cycle counts once, as busy or as the first stall cause any batch waits on (OccupancyLedger).
  Counter issue_stall_{stats_, "stall_cycles.issue_search", "cycles",
                       "the issue logic's associative search and issue cycle, when no stream runs or waits"};
  Counter sram_stall_{stats_, "stall_cycles.sram", "cycles",
                      "a stream waiting for its data (Point Buffer banks, Result Buffer slots, leader lists), when no "
                      "PE computes"};
  Counter writeback_stall_{stats_, "stall_cycles.result_writeback", "cycles",
                           "radius hits waiting for the write-back stream, when no PE computes and no stream waits "
                           "for data"};
  Counter pe_busy_cycles_{stats_, "pe_busy_cycles", "cycles",
                          "sum over PEs of the cycles each holds a query in a stream"};
  Counter bqb_max_{stats_, "bqb_max_occupancy", "count", "largest BE Query Buffer occupancy", Counter::Merge::Max};
  // Busy and stall cycles of the unit, each cycle once (batches of MQMN overlap).
  enum State : std::size_t { kBusy, kSram, kWriteback, kIssue };
  OccupancyLedger ledger_{{&busy_cycles_, &sram_stall_, &writeback_stall_, &issue_stall_}};
  Counter& distance_energy_;
  LeaderCheck leader_check_;
  StallInjector stall_;  // SU -> FE
  // PEs of running batches: computing (pe_busy_cycles), waiting for their data, or held by a
  // full write-back stream.
  Probe bqb_wave_, pes_wave_, sram_pes_wave_, writeback_pes_wave_, leaf_wave_;
};

}  // namespace tigris::hw
