// Timing-only buffer accesses. Units read and write buffer contents through DMI (function
// only); each work item then sends ONE TLM_IGNORE_COMMAND transaction per buffer carrying this
// extension, and the buffer adds the cycles its banks, ports and latency cost to the annotated
// delay (DESIGN.md section 7: never one b_transport per point). Accesses are given in bytes;
// the buffer maps them onto its own words (sram.<buffer>.word_bytes) and banks.
//
// A buffer may also hand out its TimingTarget along with its DMI pointer (a TimingHandle
// extension on the DMI request): the same charge without the generic payload, whose set-up,
// sc_time conversions and socket indirections cost more than the booking itself when a frame
// makes millions of accesses. Both ways reach the same calendar and give the same cycles.
#pragma once

#include <cstdint>

#include <tlm>

namespace tigris::tlm_if {

struct AccessProfile;

// What a buffer's timing offers directly: charge an access from cycle `start`, returning the
// cycle its data is complete (what the b_transport path returns as the annotated delay).
class TimingTarget {
 public:
  virtual std::uint64_t charge(std::uint64_t start, const AccessProfile& access) = 0;

 protected:
  ~TimingTarget() = default;
};

// Set on a get_direct_mem_ptr request; a buffer that has a TimingTarget fills it in.
struct TimingHandle : tlm::tlm_extension<TimingHandle> {
  TimingTarget* target = nullptr;
  tlm::tlm_extension_base* clone() const override { return new TimingHandle(*this); }
  void copy_from(const tlm::tlm_extension_base& other) override {
    target = static_cast<const TimingHandle&>(other).target;
  }
};

struct AccessProfile : tlm::tlm_extension<AccessProfile> {
  bool write = false;
  // Either a contiguous burst of `bytes` bytes starting at byte `first_byte` ...
  std::uint64_t first_byte = 0;
  // ... or `scatter_count` accesses at these byte addresses, of `scatter_bytes[i]` bytes each
  // (or `scatter_size` each when scatter_bytes is null).
  const std::uint64_t* scatter = nullptr;
  const std::uint32_t* scatter_bytes = nullptr;
  std::uint32_t scatter_size = 0;
  std::uint32_t scatter_count = 0;
  // With scatter: the cycle (after the start) at which an in-order pipeline issues each access;
  // a busy bank then delays that access and every later one (the pipeline stalls).
  const std::uint32_t* issue_offset = nullptr;
  std::uint64_t bytes = 0;  // payload bytes moved, for traffic and energy statistics

  std::uint32_t size_of(std::uint32_t i) const { return scatter_bytes ? scatter_bytes[i] : scatter_size; }

  tlm::tlm_extension_base* clone() const override { return new AccessProfile(*this); }
  void copy_from(const tlm::tlm_extension_base& other) override {
    *this = static_cast<const AccessProfile&>(other);
  }
};

}  // namespace tigris::tlm_if
