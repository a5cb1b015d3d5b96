// The result write-back stream: finished results leave the Result Buffer's double-buffered
// stream area for DRAM at a fixed bandwidth; writers are held back only when both halves are
// full (dram.writeback = channel). Under the paper's accounting (off_critical_path) the stream
// never holds a writer back and the channel carries only leader lists kept in DRAM. The DRAM
// region it fills is a window on the host socket, where the host driver reads the records after
// done. Time is kept relative to the job's START, so a job run again on the same accelerator
// rounds exactly as the first time.
#pragma once

#include <cstdint>
#include <vector>

#include <tlm_utils/simple_target_socket.h>
#include <systemc>
#include <tlm>

#include "hw/clock.hpp"
#include "hw/config.hpp"
#include "hw/energy_meter.hpp"
#include "hw/observer.hpp"
#include "hw/probe.hpp"
#include "hw/stall_injector.hpp"
#include "hw/stats.hpp"
#include "record_region.hpp"
#include "tlm/address_map.hpp"

namespace tigris::hw {

class ResultWriteback : public sc_core::sc_module {
 public:
  tlm_utils::simple_target_socket<ResultWriteback> socket;  // host reads of the DRAM region

  ResultWriteback(sc_core::sc_module_name name, const AcceleratorConfig& config, EnergyMeter& meter,
                  JobObserver& observer);

  // A job starts at `cycle` with `stream_buffer_bytes` of Result Buffer for the stream.
  void start(std::uint64_t cycle, std::uint64_t stream_buffer_bytes);
  // Appends records at cycle `now`; returns the cycle they are accepted (backpressure).
  std::uint64_t write(std::uint64_t now, const tlm_if::ResultRecord* records, std::size_t n);
  // Other traffic on the channel (leader lists kept in DRAM): `bytes` moved from cycle `now`,
  // behind what the channel already carries (off the critical path: other lists only);
  // returns the cycle the transfer completes.
  std::uint64_t transfer(std::uint64_t now, std::uint64_t bytes, bool write);
  // The cycle the last accepted byte reaches DRAM (off the critical path: the last record's
  // acceptance, or the last leader-list transfer's end).
  std::uint64_t drained_cycle() const;
  // Sampled simulation's functional warming (testbench/sampling.hpp): the bytes waiting in the
  // stream buffer at cycle `now`, set to what the queries it skipped would have left there.
  double backlog_bytes(std::uint64_t now) const;
  void set_backlog(std::uint64_t now, double bytes);
  std::uint64_t buffer_bytes() const { return buffer_bytes_; }
  std::uint64_t bytes() const { return region_.size(); }
  StatGroup& stats() { return stats_; }
  // The bytes waiting in the stream buffer, traced at every write.
  void attach_waves(Probe& backlog) { backlog_wave_ = &backlog; }

 private:
  void b_transport(tlm::tlm_generic_payload& trans, sc_core::sc_time& delay);
  static double dram_price(const EnergyTable& table);  // 0 when result traffic is not charged

  AcceleratorConfig::Dram config_;
  double host_bytes_per_cycle_;
  Clock clock_;
  RecordRegion region_;
  std::uint64_t origin_ = 0;       // the job's START cycle
  double drain_free_ = 0.0;        // cycles after START at which the channel is idle again
  std::uint64_t last_accept_ = 0;  // cycles after START of the last record's acceptance
  std::uint64_t buffer_bytes_ = 0;
  StatGroup stats_{"dram", "dram"};
  Counter writes_{stats_, "writes", "count", "result records written to DRAM (12 bytes each: query, index, dist2)"};
  Counter write_bytes_{stats_, "write_bytes", "bytes", "result bytes written to DRAM"};
  Counter reads_{stats_, "reads", "count", "the host's read transactions of the result region after done"};
  Counter read_bytes_{stats_, "read_bytes", "bytes",
                      "bytes the host read (the driver reads the region twice: to count per query, then to place)"};
  Counter list_writes_{stats_, "leader_list.write_bytes", "bytes",
                       "leader lists written to DRAM (approximate search, lists that did not fit)"};
  Counter list_reads_{stats_, "leader_list.read_bytes", "bytes", "leader lists read back from DRAM by followers"};
  Counter& dram_energy_;
  Counter& dram_read_energy_;
  Probe* backlog_wave_ = nullptr;
  JobObserver& observer_;
  StallInjector stall_;  // write-back grants
};

}  // namespace tigris::hw
