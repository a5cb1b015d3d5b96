// A waveform probe: a unit records its state changes (busy flags, occupancies, query ids)
// through it, and they reach the VCD only when waves were asked for (tigris run --vcd).
#pragma once

#include <cstdint>
#include <string>

#include <systemc>

#include "clock.hpp"
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
    if (vcd_) set_at(sc_core::sc_time_stamp(), value);
  }
  // A change booked for `t` (now or later); a probe's own changes are booked in time order.
  void set_at(const sc_core::sc_time& t, std::uint64_t value) {
    if (!vcd_) return;
    if (total_) total_->add_at(t, static_cast<std::int64_t>(value) - static_cast<std::int64_t>(last_));
    last_ = value;
    vcd_->change_at(id_, ps(t), value, ps(sc_core::sc_time_stamp()));
  }
  // The same at cycle `c` of `clock`: its time is made only when waves are on (a library call
  // for every unit's every step otherwise).
  void set_at(const Clock& clock, std::uint64_t c, std::uint64_t value) {
    if (vcd_) set_at(clock.at(c), value);
  }
  void add_at(const Clock& clock, std::uint64_t c, std::int64_t delta) {
    if (vcd_) add_at(clock.at(c), delta);
  }
  // Adds `delta` from `t` (now or later) on: a count several overlapping things change.
  void add_at(const sc_core::sc_time& t, std::int64_t delta) {
    if (!vcd_ || delta == 0) return;
    if (total_) total_->add_at(t, delta);
    vcd_->add_at(id_, ps(t), delta, ps(sc_core::sc_time_stamp()));
  }

 private:
  static std::uint64_t ps(const sc_core::sc_time& t) {
    return static_cast<std::uint64_t>(t / sc_core::sc_time(1, sc_core::SC_PS));
  }
  VcdWriter* vcd_ = nullptr;
  Probe* total_ = nullptr;
  std::uint64_t last_ = 0;
  int id_ = 0;
};

// The aggregate traces a waveform viewer should show first (summed over units). Busy counts
// match the statistics' busy cycles; each stall cause has its own count, so their time averages
// are the summary's utilizations and stall shares.
struct AggregateProbes {
  Probe rus_busy, rus_sram_stall, rus_bqb_full_stall, rus_writeback_stall;
  Probe busy_pes, pes_sram_stall, pes_writeback_stall;
  Probe bqb_occupancy, queries_finished, writeback_backlog;
};

}  // namespace tigris::hw
