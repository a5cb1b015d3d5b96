// A global-buffer SRAM (Point, Query, Query Stack or Result Buffer): word-interleaved banks,
// a port limit and a read latency. Each bank keeps a calendar of its busy cycles, so accesses
// to a busy bank wait for its next free cycle (contention); nothing runs per cycle.
//
// Reached over TLM-2.0: host READ/WRITE transactions copy data (and are timed as bursts);
// units use DMI for data and TLM_IGNORE_COMMAND + AccessProfile for timing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <systemc>
#include <tlm>
#include <tlm_utils/multi_passthrough_target_socket.h>

#include "hw/config.hpp"
#include "hw/mem/bank_calendar.hpp"
#include "hw/stats.hpp"
#include "tlm/access_profile.hpp"

namespace tigris::hw {

class BankedSram : public sc_core::sc_module {
 public:
  tlm_utils::multi_passthrough_target_socket<BankedSram> socket;

  BankedSram(sc_core::sc_module_name name, const SramConfig& config, sc_core::sc_time period);

  std::uint8_t* data() { return data_.data(); }
  std::uint64_t size() const { return data_.size(); }
  const BufferStats& stats() const { return stats_; }
  void reset_stats() { stats_ = {}; }  // at START: the host's loads are not the job's traffic

  // Charges an access starting at cycle `start`; returns the cycle its data is complete.
  std::uint64_t charge(std::uint64_t start, const tlm_if::AccessProfile& access);

 private:
  std::uint64_t charge_in_order(std::uint64_t start, const tlm_if::AccessProfile& access);
  std::uint64_t current_cycle() const;
  void b_transport(int id, tlm::tlm_generic_payload& trans, sc_core::sc_time& delay);
  bool get_direct_mem_ptr(int id, tlm::tlm_generic_payload& trans, tlm::tlm_dmi& dmi);
  unsigned int transport_dbg(int id, tlm::tlm_generic_payload& trans);

  SramConfig config_;
  sc_core::sc_time period_;
  std::vector<std::uint8_t> data_;
  std::vector<BankCalendar> banks_;
  BufferStats stats_;
};

}  // namespace tigris::hw
