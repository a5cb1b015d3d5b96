// Recursion Unit (paper section 5.2): walks one query's top-tree part of the depth-first
// search at a time, stages FQ RS RN CD PI CL. One activation (from taking the query out of the
// FQQ to sending it to a leaf set, or finishing it) is one work item, walked by the unit's
// engine (walk_engine.hpp: the transaction-level walk or the RTL RU); the unit hands the query
// on, keeps its statistics and sends a finished query's results.
#pragma once

#include <cstdint>
#include <optional>
#include <tuple>
#include <vector>

#include <systemc>

#include "hw/clock.hpp"
#include "hw/config.hpp"
#include "hw/energy_meter.hpp"
#include "hw/host/scan_service.hpp"
#include "hw/job.hpp"
#include "hw/mem/banked_sram.hpp"
#include "hw/mem/buffer_port.hpp"
#include "hw/mem/result_slots.hpp"
#include "hw/observer.hpp"
#include "hw/probe.hpp"
#include "hw/scheduler.hpp"
#include "hw/stall_injector.hpp"
#include "hw/stats.hpp"
#include "hw/tree_view.hpp"
#include "walk_engine.hpp"

namespace tigris::hw {

class FrontEnd;
class DistributionNetwork;
class ResultBuffer;

class RecursionUnit : public sc_core::sc_module, private Scheduler::Client {
 public:
  BufferPort points, queries, stacks, results;

  // What a Recursion Unit works with: the blocks it hands queries and results to.
  struct Links {
    FrontEnd& fe;
    DistributionNetwork& qdn;
    ResultBuffer& result_buffer;
    EnergyMeter& meter;
    JobObserver& observer;
    Scheduler& scheduler;
    ScanService& scans;  // the query's slot may still be written by its last scan (deferred results)
    WalkEngine& engine;  // walks the activations (fe.recursion_unit_model: tlm or rtl)
  };
  RecursionUnit(sc_core::sc_module_name name, int id, const AcceleratorConfig& config, const JobDescriptor& job,
                Links links);

  int id() const { return id_; }
  void start_job();                     // views onto the new job's data through the ports
  void start(const QueryToken& token);  // the FE hands over a query; the RU must be idle
  void retry_dispatch();                // the BE Query Buffer it waits for has room again
  // A walk of `token` is a few dispatches away: tells the scan service (the host's seam, no
  // hardware) what the walk will read first (its query record, stack and result slot), so the
  // host may warm its cache.
  void walk_soon(const QueryToken& token) const;
  StatGroup& stats() { return stats_; }
  bool busy_flag() const { return state_ != State::Idle; }
  std::uint32_t current_query() const { return token_.query; }
  // Blocked: its query waits for room in the BE Query Buffer of the SU serving `blocked_leaf()`.
  bool blocked() const { return state_ == State::Blocked; }
  std::uint32_t blocked_leaf() const { return token_.leaf; }
  void attach_waves(VcdWriter& vcd, const std::string& scope, AggregateProbes& all) {
    busy_wave_.feed(all.rus_busy);
    sram_wave_.feed(all.rus_sram_stall);
    stalled_wave_.feed(all.rus_bqb_full_stall);
    writeback_wave_.feed(all.rus_writeback_stall);
    busy_wave_.attach(vcd, scope + ".busy", 1);
    sram_wave_.attach(vcd, scope + ".sram_stall", 1);
    stalled_wave_.attach(vcd, scope + ".bqb_full_stall", 1);
    writeback_wave_.attach(vcd, scope + ".writeback_stall", 1);
    query_wave_.attach(vcd, scope + ".query", 32);
  }

 private:
  enum class State { Idle, Walking, Blocked };
  void on_done();
  // Walks the activation from cycle `now` through the engine; sets token_ and finished_, adds
  // the walk's statistics. Returns (its pipeline cycles with the grant stalls, the cycle its
  // last access is complete, the grant stalls).
  std::tuple<std::uint64_t, std::uint64_t, std::uint64_t> walk(std::uint64_t now);
  void clear_results();  // a new query's slot (NN/kNN) or radius staging starts empty

  int id_;
  const AcceleratorConfig& config_;
  const CostTable& cost_;
  const JobDescriptor& job_;
  Links links_;
  Clock clock_;
  TreeView tree_;
  ResultSlots slots_;
  const tlm_if::QueryRecord* query_records_ = nullptr;
  // The Point, Query and Query Stack Buffers behind the ports, when they are global buffers: a
  // walk's one-word accesses take their short path inline (BufferPort::request).
  BankedSram *points_sram_ = nullptr, *queries_sram_ = nullptr, *stacks_sram_ = nullptr;
  StackEntry* stacks_ = nullptr;

  State state_ = State::Idle;
  QueryToken token_;
  bool finished_ = false;
  std::uint64_t blocked_since_ = 0;
  void wake() override { on_done(); }
  StatGroup stats_;
  Counter activations_{stats_, "activations", "count", "queries taken from the FQQ: one walk each"};
  Counter busy_cycles_{stats_, "busy_cycles", "cycles",
                       "pipeline cycles of the walks (FQ, nodes, prunes, drain, and the PI->RS stalls)"};
  Counter pi_rs_stall_{stats_, "stall_cycles.pi_rs_dependency", "cycles",
                       "PI->RS dependency stalls without forwarding; part of `busy_cycles` (so not added again to "
                       "the bottleneck's occupancy)"};
  Counter sram_stall_{stats_, "stall_cycles.sram", "cycles",
                      "a walk waiting for buffer banks or ports beyond its pipeline cycles"};
  Counter bqb_full_stall_{stats_, "stall_cycles.bqb_full", "cycles", "holding a query whose BE Query Buffer is full"};
  Counter writeback_stall_{stats_, "stall_cycles.result_writeback", "cycles",
                           "finished results (NN/kNN lists, radius hits at top nodes) waiting for the write-back "
                           "stream"};
  Counter prune_cycles_{stats_, "prune_cycles", "cycles", "the part of `busy_cycles` spent on pruned nodes"};
  Counter& node_energy_;
  Counter& replica_bytes_;              // node reads from the RU's own top-level copy
  std::uint32_t replicated_nodes_ = 0;  // heap nodes below this id are in the copy
  StallInjector stall_;                 // the hand-off to the QDN (or the finish)
  // busy: the pipeline cycles (busy_cycles); then a stall, each cause its own wave.
  Probe busy_wave_, sram_wave_, stalled_wave_, writeback_wave_, query_wave_;
  std::vector<tlm_if::ResultRecord> hits_;  // radius hits found at top nodes
  // first_leaf: a finished leader's record, sent when its results have left (on_done).
  std::optional<LeaderRecord> record_;
  void take_leader_record();
};

}  // namespace tigris::hw
