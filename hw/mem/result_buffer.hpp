// The Result Buffer (paper section 5.2): one SRAM split between the NN/kNN query slots (the
// `result_buffer.slot_fraction` share; layout in result_slots.hpp), under approximate search the
// leaders' local result lists (the `result_buffer.leader_fraction` share after the slots), and
// the double-buffered stream area that the write-back drains to DRAM. Radius search keeps no
// slots: every hit is streamed.
#pragma once

#include <cstdint>

#include <systemc>

#include "banked_sram.hpp"
#include "hw/config.hpp"
#include "hw/energy_meter.hpp"
#include "leader_staging.hpp"
#include "result_writeback.hpp"

namespace tigris::hw {

class ResultBuffer : public sc_core::sc_module {
 public:
  ResultBuffer(sc_core::sc_module_name name, const AcceleratorConfig& config, EnergyMeter& meter, JobObserver& observer)
      : sc_module(name), sram_("results", config.sram.results, Clock{config.period()}, meter, config.stall),
        writeback_("writeback", config, meter, observer) {}

  // The units' way to the slots (DMI data, timed accesses), and the host's to the DRAM region.
  tlm_utils::multi_passthrough_target_socket<BankedSram>& socket() { return sram_.socket; }
  tlm_utils::simple_target_socket<ResultWriteback>& dram_socket() { return writeback_.socket; }
  StatGroup& sram_stats() { return sram_.stats(); }
  StatGroup& dram_stats() { return writeback_.stats(); }

  // How many query slots of `slot_bytes` the slot share holds (0 bytes: no slots needed).
  static std::uint64_t slot_capacity(const AcceleratorConfig& config, std::uint64_t slot_bytes) {
    if (slot_bytes == 0) return ~std::uint64_t{0};
    const double share = static_cast<double>(config.sram.results.bytes) * config.result_buffer.slot_fraction;
    return static_cast<std::uint64_t>(share) / slot_bytes;
  }
  // Bytes for leader lists when a job searches approximately.
  static std::uint64_t leader_area_bytes(const AcceleratorConfig& config) {
    return static_cast<std::uint64_t>(static_cast<double>(config.sram.results.bytes) *
                                      config.result_buffer.leader_fraction);
  }
  // A job starts at `cycle` with `slots` query slots of `slot_bytes` and `leader_bytes` of leader
  // lists; the rest is stream area.
  void start(std::uint64_t cycle, std::uint64_t slots, std::uint64_t slot_bytes, std::uint64_t leader_bytes) {
    sram_.start();
    writeback_.start(cycle, sram_.size() - slots * slot_bytes - leader_bytes);
  }
  // A leader list kept in DRAM: `bytes` written or read over the write-back's channel from
  // cycle `now`; returns the cycle the transfer completes.
  std::uint64_t dram_transfer(std::uint64_t now, std::uint64_t bytes, bool write) {
    return writeback_.transfer(now, bytes, write);
  }
  // Streams records out at cycle `now`; returns the cycle they are accepted.
  std::uint64_t stream(std::uint64_t now, const tlm_if::ResultRecord* records, std::size_t n) {
    return writeback_.write(now, records, n);
  }
  std::uint64_t drained_cycle() const { return writeback_.drained_cycle(); }  // last byte in DRAM
  ResultWriteback& writeback() { return writeback_; }
  void attach_waves(Probe& backlog) { writeback_.attach_waves(backlog); }
  std::uint64_t streamed_bytes() const { return writeback_.bytes(); }
  LeaderStaging& leader_staging() { return staging_; }  // first_leaf leaders' lists in the making

 private:
  BankedSram sram_;            // slots and stream area, bank by bank
  ResultWriteback writeback_;  // the stream to DRAM (a host window)
  LeaderStaging staging_;
};

}  // namespace tigris::hw
