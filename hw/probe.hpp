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
  void set(std::uint64_t value) {
    if (vcd_) vcd_->change(id_, static_cast<std::uint64_t>(sc_core::sc_time_stamp() / sc_core::sc_time(1, sc_core::SC_PS)), value);
  }

 private:
  VcdWriter* vcd_ = nullptr;
  int id_ = 0;
};

}  // namespace tigris::hw
