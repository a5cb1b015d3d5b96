// A unit's port onto one global buffer: DMI for the data, one timing-only TLM transaction per
// work item for the cost (see tlm/access_profile.hpp).
#pragma once

#include <cstdint>

#include <systemc>
#include <tlm>
#include <tlm_utils/simple_initiator_socket.h>

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

  // The buffer's storage, fetched once through DMI.
  std::uint8_t* data() {
    if (!dmi_ptr_) {
      tlm::tlm_generic_payload t;
      t.set_address(0);
      t.set_command(tlm::TLM_READ_COMMAND);
      tlm::tlm_dmi dmi;
      if (!socket->get_direct_mem_ptr(t, dmi)) SC_REPORT_FATAL("tigris", "buffer refused DMI");
      dmi_ptr_ = dmi.get_dmi_ptr();
    }
    return dmi_ptr_;
  }

  // Charges `access` starting at cycle `start`; returns the cycle it completes.
  std::uint64_t charge(std::uint64_t start, const tlm_if::AccessProfile& access,
                       const sc_core::sc_time& period) {
    if (access.bytes == 0 && access.scatter_count == 0) return start;  // nothing to access
    profile_ = access;
    trans_.set_command(tlm::TLM_IGNORE_COMMAND);
    trans_.set_address(access.scatter ? 0 : access.first_byte);
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
  tlm::tlm_generic_payload trans_;
  tlm_if::AccessProfile profile_;
  unsigned char dummy_ = 0;
  std::uint8_t* dmi_ptr_ = nullptr;
};

}  // namespace tigris::hw
