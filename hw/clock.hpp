// The accelerator's clock: SystemC time <-> cycles. No process ticks it (docs/model.md).
#pragma once

#include <cstdint>

#include <systemc>

namespace tigris::hw {

// Integer arithmetic on the time's value (in SystemC's resolution): every time the model
// notifies is a whole number of periods, and sc_time's double arithmetic is slow.
struct Clock {
  sc_core::sc_time period;
  // The current time's value, read inline (sc_time_stamp() is a call into the library).
  static std::uint64_t time_value() { return sc_core::sc_get_curr_simcontext()->time_stamp().value(); }
  // The current cycle; the division is done once per time step, not per call.
  std::uint64_t now() const {
    const std::uint64_t t = time_value();
    if (t != seen_time_) seen_time_ = t, seen_cycle_ = t / period.value();
    return seen_cycle_;
  }
  // Cycle `c` as a time.
  sc_core::sc_time at(std::uint64_t c) const { return sc_core::sc_time::from_value(c * period.value()); }
  // The delay from now until cycle `c` (c >= now).
  sc_core::sc_time until(std::uint64_t c) const { return at(c - now()); }

  // The last time now() saw and its cycle (public only so that Clock{period} stays an aggregate).
  mutable std::uint64_t seen_time_ = ~std::uint64_t{0}, seen_cycle_ = 0;
};

}  // namespace tigris::hw
