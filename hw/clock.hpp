// The accelerator's clock: SystemC time <-> cycles. No process ticks it (DESIGN.md section 7).
#pragma once

#include <cstdint>

#include <systemc>

namespace tigris::hw {

struct Clock {
  sc_core::sc_time period;
  std::uint64_t now() const { return static_cast<std::uint64_t>(sc_core::sc_time_stamp() / period); }
  // The delay from now until cycle `c` (c >= now).
  sc_core::sc_time until(std::uint64_t c) const { return (c - now()) * period; }
};

}  // namespace tigris::hw
