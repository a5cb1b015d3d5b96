// The accelerator's clock: SystemC time <-> cycles. No process ticks it (DESIGN.md section 7).
#pragma once

#include <cstdint>

#include <systemc>

namespace tigris::hw {

// Integer arithmetic on the time's value (in SystemC's resolution): every time the model
// notifies is a whole number of periods, and sc_time's double arithmetic is slow.
struct Clock {
  sc_core::sc_time period;
  std::uint64_t now() const { return sc_core::sc_time_stamp().value() / period.value(); }
  // Cycle `c` as a time.
  sc_core::sc_time at(std::uint64_t c) const { return sc_core::sc_time::from_value(c * period.value()); }
  // The delay from now until cycle `c` (c >= now).
  sc_core::sc_time until(std::uint64_t c) const { return at(c - now()); }
};

}  // namespace tigris::hw
