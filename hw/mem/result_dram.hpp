// The result stream: finished results leave the Result Buffer's double-buffered stream area
// for DRAM at a fixed bandwidth. Writers are held back only when both halves are full. The DRAM
// region is a window on the host socket, where the host driver reads the records after done.
#pragma once

#include <cstdint>
#include <vector>

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_target_socket.h>

#include "hw/config.hpp"
#include "tlm/address_map.hpp"

namespace tigris::hw {

class ResultDram : public sc_core::sc_module {
 public:
  tlm_utils::simple_target_socket<ResultDram> socket;  // host reads of the result region

  ResultDram(sc_core::sc_module_name name, const AcceleratorConfig& config);

  void reset(std::uint64_t stream_buffer_bytes);
  void start(std::uint64_t cycle) { drain_free_ = static_cast<double>(cycle); }
  // Appends records at cycle `now`; returns the cycle they are accepted (backpressure).
  std::uint64_t write(std::uint64_t now, const tlm_if::ResultRecord* records, std::size_t n);
  // The cycle the last accepted byte reaches DRAM.
  std::uint64_t drained_cycle() const;
  std::uint64_t bytes() const { return region_.size(); }
  std::uint64_t stall_cycles() const { return stall_cycles_; }

 private:
  void b_transport(tlm::tlm_generic_payload& trans, sc_core::sc_time& delay);

  AcceleratorConfig::Dram config_;
  double host_bytes_per_cycle_;
  sc_core::sc_time period_;
  std::vector<std::uint8_t> region_;
  double drain_free_ = 0.0;  // cycle at which the write-back channel is idle again
  std::uint64_t buffer_bytes_ = 0;
  std::uint64_t stall_cycles_ = 0;
};

}  // namespace tigris::hw
