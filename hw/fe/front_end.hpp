// Front-end (paper section 5.2): the FE Query Queue and the Recursion Units. New queries are
// admitted when a Query Stack Buffer slot is free (a slot also reserves an FQQ entry, so the
// back-end can always re-insert a scanned query and the FQQ never deadlocks the machine).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <systemc>

#include "hw/clock.hpp"
#include "hw/config.hpp"
#include "hw/host/fifo_ring.hpp"
#include "hw/job.hpp"
#include "hw/probe.hpp"
#include "hw/scheduler.hpp"
#include "hw/stall_injector.hpp"
#include "hw/stats.hpp"
#include "recursion_unit.hpp"

namespace tigris::hw {

class FrontEnd : public sc_core::sc_module, private Scheduler::Client {
 public:
  std::vector<std::unique_ptr<RecursionUnit>> rus;

  // Builds the Recursion Units (in reverse id order when `reverse_construction`: a test that
  // the figures do not depend on it); their links point at this front-end.
  FrontEnd(sc_core::sc_module_name name, const AcceleratorConfig& config, const JobDescriptor& job,
           DistributionNetwork& qdn, ResultBuffer& result_buffer, EnergyMeter& meter, JobObserver& observer,
           Scheduler& scheduler, ScanService& scans, bool reverse_construction = false);

  // Starts a job: admits the first queries. `on_all_done(cycle)` fires once all finished.
  void start(std::function<void(std::uint64_t)> on_all_done);
  StatGroup& stats() { return stats_; }

  void reinsert(QueryToken token, std::uint64_t ready_cycle);  // from a Search Unit
  void ru_idle(RecursionUnit& ru);
  void query_finished(const QueryToken& token, std::uint64_t cycle);  // from an RU, or an SU (a follower)
  // first_leaf: a leader's record left for its Leader Buffer / was applied there. The job is
  // done when every query has finished and every record has arrived.
  void leader_record_sent() { ++records_in_flight_; }
  void leader_record_delivered(std::uint64_t cycle);

  void set_progress(std::function<void(std::uint32_t, std::uint32_t)> progress) { progress_ = std::move(progress); }
  std::size_t fqq_occupancy() const { return fqq_.size(); }
  void attach_waves(VcdWriter& vcd, const std::string& scope, AggregateProbes& all) {
    fqq_wave_.attach(vcd, scope + ".fqq_occupancy", 32);
    finished_wave_.feed(all.queries_finished);
    finished_wave_.attach(vcd, scope + ".queries_finished", 32);
    for (std::size_t i = 0; i < rus.size(); ++i) rus[i]->attach_waves(vcd, scope + ".ru" + std::to_string(i), all);
  }
  std::uint32_t finished() const { return finished_; }
  std::uint32_t admitted() const { return next_query_; }
  // Test-only fault: re-inserted queries are dropped, so the job can never finish (the
  // deadlock report's test provokes a stuck machine with it).
  void drop_reinserted_for_test(bool drop) { drop_reinserted_ = drop; }

 private:
  void wake() override { dispatch(); }
  void dispatch();  // idle RUs take ready queries from the FQQ
  void push(const QueryToken& token);
  bool admit(std::uint64_t cycle);  // a new query takes a free slot, if there is one

  static constexpr std::size_t kPrefetchAhead = 8;  // dispatches ahead; see dispatch()
  const JobDescriptor& job_;
  JobObserver& observer_;
  std::unique_ptr<WalkEngine> engine_;  // fe.recursion_unit_model, or null for the TLM walk
  Clock clock_;
  FifoRing<QueryToken> fqq_;
  std::vector<RecursionUnit*> idle_rus_;
  std::vector<std::uint32_t> free_slots_;
  void check_all_done(std::uint64_t cycle);
  std::uint32_t next_query_ = 0, finished_ = 0;
  std::uint64_t records_in_flight_ = 0;
  bool drop_reinserted_ = false;
  std::function<void(std::uint64_t)> on_all_done_;
  std::function<void(std::uint32_t, std::uint32_t)> progress_;
  Scheduler& scheduler_;
  StatGroup stats_{"fe", "front_end"};
  StallInjector stall_;  // FQQ -> RU
  Counter fqq_max_{stats_, "max_occupancy", "count", "largest number of query tokens in the FE Query Queue",
                   Counter::Merge::Max};
  Counter in_flight_{stats_, "queries_in_flight", "count",
                     "queries the job may hold in flight: the smallest of Query Stack slots, FQQ entries, Result "
                     "Buffer slots (NN/kNN) and the query count",
                     Counter::Merge::Max};
  Probe fqq_wave_, finished_wave_;
};

}  // namespace tigris::hw
