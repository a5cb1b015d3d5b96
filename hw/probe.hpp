// A waveform probe: a unit records its state changes (busy flags, occupancies, query ids)
// through it, and they reach the VCD only when waves were asked for (tigris run --vcd).
#pragma once

#include <cstdint>
#include <string>

#include <systemc>

#include "traces/vcd_writer.hpp"

namespace tigris::hw {

class Probe {
 public:
  void attach(VcdWriter& vcd, const std::string& name, int width) {
    vcd_ = &vcd;
    id_ = vcd.add(name, width);
  }
  // Also adds this probe's changes into `total` (an aggregate trace over units of a kind).
  void feed(Probe& total) { total_ = &total; }
  void set(std::uint64_t value) {
    if (!vcd_) return;
    if (total_) total_->set(total_->last_ + value - last_);
    last_ = value;
    vcd_->change(id_, static_cast<std::uint64_t>(sc_core::sc_time_stamp() / sc_core::sc_time(1, sc_core::SC_PS)), value);
  }

 private:
  VcdWriter* vcd_ = nullptr;
  Probe* total_ = nullptr;
  std::uint64_t last_ = 0;
  int id_ = 0;
};

// The aggregate traces a waveform viewer should show first (summed over units).
struct AggregateProbes {
  Probe rus_busy, busy_pes, bqb_occupancy, queries_finished, writeback_backlog;
};

}  // namespace tigris::hw
