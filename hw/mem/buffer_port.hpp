// A unit's port onto one global buffer: DMI for the data, one timing-only charge per work item
// for the cost (see tlm/access_profile.hpp): straight to the buffer's TimingTarget when it
// offers one with its DMI pointer, else as a TLM_IGNORE_COMMAND b_transport.
#pragma once

#include <algorithm>
#include <cstdint>

#include <tlm_utils/simple_initiator_socket.h>
#include <systemc>
#include <tlm>

#include "hw/clock.hpp"
#include "tlm/access_profile.hpp"

namespace tigris::hw {

class BufferPort {
 public:
  explicit BufferPort(const char* name) : socket(name) { trans_.set_extension(&profile_); }
  ~BufferPort() { trans_.clear_extension(&profile_); }
  BufferPort(const BufferPort&) = delete;
  BufferPort& operator=(const BufferPort&) = delete;

  tlm_utils::simple_initiator_socket<BufferPort> socket;

  // The buffer's storage (and its TimingTarget, if it has one), fetched once through DMI.
  std::uint8_t* data() {
    if (!dmi_ptr_) {
      tlm::tlm_generic_payload t;
      t.set_address(0);
      t.set_command(tlm::TLM_READ_COMMAND);
      tlm_if::TimingHandle handle;
      t.set_extension(&handle);
      tlm::tlm_dmi dmi;
      const bool granted = socket->get_direct_mem_ptr(t, dmi);
      t.clear_extension(&handle);
      if (!granted) SC_REPORT_FATAL("tigris", "buffer refused DMI");
      dmi_ptr_ = dmi.get_dmi_ptr();
      timing_ = use_transport_ ? nullptr : handle.target;
    }
    return dmi_ptr_;
  }
  // Test hook: time every access with a b_transport, even where a TimingTarget is offered.
  void use_transport_for_timing() { use_transport_ = true, timing_ = nullptr; }
  // The buffer's TimingTarget (after data()), or null when timing goes through b_transport.
  tlm_if::TimingTarget* timing_target() const { return timing_; }

  // One access a unit requests at cycle `cycle` and holds until it is granted (the Recursion
  // Unit's request/grant ports): books `bytes` at `byte`; returns the cycle it is granted (its
  // last word served), and raises `complete` to the cycle its data is complete (the grant, then
  // the buffer's `latency`).
  std::uint64_t request(std::uint64_t cycle, std::uint64_t byte, std::uint32_t bytes, bool write, int latency,
                        const sc_core::sc_time& period, std::uint64_t& complete) {
    return granted(charge_one(cycle, byte, bytes, write, period), latency, complete);
  }
  // The same through `buffer` (null: as above), the buffer's own class when the caller knows it
  // (hw/mem/banked_sram.hpp, final): its charge_one() inline in the caller's loop. (A template:
  // rtl/, linked before hw/, instantiates only the one above.)
  template <class Buffer>
  std::uint64_t request(Buffer* buffer, std::uint64_t cycle, std::uint64_t byte, std::uint32_t bytes, bool write,
                        int latency, const sc_core::sc_time& period, std::uint64_t& complete) {
    const std::uint64_t c =
        buffer ? buffer->charge_one(cycle, byte, bytes, write) : charge_one(cycle, byte, bytes, write, period);
    return granted(c, latency, complete);
  }

  // Charges `access` starting at cycle `start`; returns the cycle it completes.
  std::uint64_t charge(std::uint64_t start, const tlm_if::AccessProfile& access, const sc_core::sc_time& period) {
    if (access.bytes == 0 && access.scatter_count == 0 && access.pipeline_count == 0) return start;  // nothing
    if (timing_) return timing_->charge(start, access);
    profile_ = access;
    trans_.set_command(tlm::TLM_IGNORE_COMMAND);
    trans_.set_address(access.scatter || access.pipeline ? 0 : access.first_byte);
    trans_.set_data_ptr(&dummy_);
    trans_.set_data_length(0);
    trans_.set_response_status(tlm::TLM_INCOMPLETE_RESPONSE);
    // Integer time values: every time here is a whole number of periods (see hw/clock.hpp).
    const std::uint64_t now = Clock::time_value(), p = period.value();
    sc_core::sc_time delay = sc_core::sc_time::from_value(start * p - now);
    socket->b_transport(trans_, delay);
    return (now + delay.value()) / p;
  }

 private:
  // An access complete at cycle `c` was granted `latency` + 1 cycles before; `complete` takes it.
  static std::uint64_t granted(std::uint64_t c, int latency, std::uint64_t& complete) {
    complete = std::max(complete, c);
    return c - 1 - static_cast<std::uint64_t>(latency);
  }
  // request()'s access through the TimingTarget, else a b_transport (out of line: the template's
  // short path is inlined into the walk's loop).
  __attribute__((noinline)) std::uint64_t charge_one(std::uint64_t cycle, std::uint64_t byte, std::uint32_t bytes,
                                                     bool write, const sc_core::sc_time& period) {
    if (timing_) return timing_->charge_one(cycle, byte, bytes, write);
    const tlm_if::PipelineAccess one{byte, bytes, 0};
    return charge(cycle, tlm_if::AccessProfile::single(one, write), period);
  }

  tlm::tlm_generic_payload trans_;
  tlm_if::AccessProfile profile_;
  unsigned char dummy_ = 0;
  std::uint8_t* dmi_ptr_ = nullptr;
  tlm_if::TimingTarget* timing_ = nullptr;
  bool use_transport_ = false;
};

}  // namespace tigris::hw
