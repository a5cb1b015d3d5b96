// The Tigris accelerator: front-end, Query Distribution Network, back-end, global buffers,
// Node Cache and the Result Buffer with its write-back, behind one host-facing TLM-2.0 target
// socket (CSRs and windows onto the buffers, tlm/address_map.hpp) and a done interrupt.
// Statistics are a tree under stats(); observers see every walk and leaf visit.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <tlm_utils/simple_target_socket.h>
#include <systemc>
#include <tlm>

#include "config.hpp"
#include "energy_meter.hpp"
#include "hw/be/issue_policy.hpp"
#include "hw/be/node_cache.hpp"
#include "hw/be/search_unit.hpp"
#include "hw/fe/front_end.hpp"
#include "hw/host/scan_service.hpp"
#include "hw/mem/banked_sram.hpp"
#include "hw/mem/buffer_port.hpp"
#include "hw/mem/result_buffer.hpp"
#include "hw/qdn/distribution_network.hpp"
#include "job.hpp"
#include "observer.hpp"
#include "scheduler.hpp"
#include "stats.hpp"

namespace tigris::hw {

// How the simulator runs on the host, none of it hardware; the figures are the same either way
// (tests check).
struct HostOptions {
  // Builds the RUs and SUs in reverse id order: the figures must not depend on it, since
  // same-cycle work runs in unit order (hw/scheduler.hpp).
  bool reverse_construction = false;
  bool scan_thread = false;  // exact NN/kNN scans on a second host thread (hw/host/scan_service.hpp)
};

class TigrisAccelerator : public sc_core::sc_module {
  // Declared first: the units below keep references to them, so they must be built first.
  AcceleratorConfig config_;
  JobDescriptor job_;
  EnergyMeter meter_;
  ObserverList observers_;
  StatGroup stats_{"tigris"};
  StatGroup be_stats_{"be"};
  std::unique_ptr<ScanService> scans_;  // the host's speed-ups, no hardware (hw/host/scan_service.hpp)

 public:
  SC_HAS_PROCESS(TigrisAccelerator);
  tlm_utils::simple_target_socket<TigrisAccelerator> host;
  sc_core::sc_out<bool> irq;

  TigrisAccelerator(sc_core::sc_module_name name, const AcceleratorConfig& config,
                    const HostOptions& host_options = {});
  ~TigrisAccelerator() override { scans_->drain(); }  // no scan may outlive its Search Unit

  const AcceleratorConfig& config() const { return config_; }
  const JobDescriptor& job() const { return job_; }  // the last job started
  std::uint64_t job_cycles() const { return done_cycle_ - start_cycle_; }
  std::uint64_t start_cycle() const { return start_cycle_; }  // of the last job started
  bool done() const { return done_; }
  const std::string& error() const { return error_; }  // why the last START was rejected

  // The statistics tree (reset at every START): fe (ru*), qdn, be (su*), the buffers,
  // node_cache, result_writeback and the energy meter's counts.
  const StatGroup& stats() const { return stats_; }
  // The energy meter's picojoules, with `leakage_pj` (hw/area_model.hpp) added.
  nlohmann::json energy_pj(double leakage_pj) const { return meter_.energy_pj(leakage_pj); }
  // Sampled simulation (testbench/sampling.hpp) writes the job's estimate over the statistics.
  void set_stat_values(const std::vector<std::uint64_t>& values) { stats_.set_values(values); }
  // ... and warms the result write-back's backlog at a seam of its stream.
  ResultWriteback& writeback() { return result_buffer_.writeback(); }
  std::uint64_t now_cycle() const { return clock_.now(); }
  void attach_observer(JobObserver& observer) { observers_.attach(observer); }
  // A host speed-up: `hint` hears of each query shortly before the observers do.
  void attach_hint(QueryHint& hint) { scans_->attach(hint); }
  // What every queue and unit holds: the report of a run that stopped before it finished.
  std::string describe_state() const;
  // Records unit busy flags, queue occupancies and query ids into `vcd` from now on.
  void attach_waves(VcdWriter& vcd);
  FrontEnd& front_end_for_test() { return fe_; }
  // Test hook: every unit times its buffer accesses with b_transport instead of the buffers'
  // TimingTarget (tlm/access_profile.hpp); the figures must not change.
  void time_through_transport_for_test();
  void set_progress(std::function<void(std::uint32_t, std::uint32_t)> progress) { progress_ = std::move(progress); }

 private:
  void host_b_transport(tlm::tlm_generic_payload& trans, sc_core::sc_time& delay);
  unsigned int host_transport_dbg(tlm::tlm_generic_payload& trans);
  void csr_access(tlm::tlm_generic_payload& trans);
  void do_start();   // SC_METHOD on start_
  void do_finish();  // SC_METHOD on finish_
  void drive_irq();  // SC_METHOD: the one writer of irq, level = STATUS done or error
  void fail(std::uint32_t code);
  // Decodes the CSRs into job_; returns an empty string when the job fits, else why not.
  std::string configure_job();

  Clock clock_;
  Scheduler scheduler_;
  BankedSram points_, queries_, query_stack_;
  ResultBuffer result_buffer_;
  NodeCache node_cache_;
  DistributionNetwork qdn_;
  FrontEnd fe_;
  std::vector<std::unique_ptr<SearchUnit>> sus_;
  BufferPort to_points_, to_queries_;  // the host's way in, and the leaf-directory check's DMI
  tlm_utils::simple_initiator_socket<TigrisAccelerator> to_dram_;

  std::uint32_t csr_[tlm_if::kCsrCount] = {};
  sc_core::sc_event start_, finish_, irq_changed_;
  std::uint64_t start_cycle_ = 0, done_cycle_ = 0;
  bool done_ = false;
  std::string error_;
  std::function<void(std::uint32_t, std::uint32_t)> progress_;
  AggregateProbes waves_;
};

}  // namespace tigris::hw
