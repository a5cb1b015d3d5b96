// Timing-only buffer accesses. Units read and write buffer contents through DMI (function
// only); each work item then sends ONE TLM_IGNORE_COMMAND transaction per buffer carrying this
// extension, and the buffer adds the cycles its banks, ports and latency cost to the annotated
// delay (docs/model.md, timing: never one b_transport per point). Accesses are given in bytes;
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
  // One access of `bytes` at byte `byte` from cycle `start`: what a one-entry pipeline profile
  // charges, for a unit that books its accesses one at a time (the Recursion Unit's steps).
  virtual std::uint64_t charge_one(std::uint64_t start, std::uint64_t byte, std::uint32_t bytes, bool write) = 0;

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

// One access of an in-order pipeline: `bytes` bytes at byte `byte`, issued `issue_offset`
// cycles after the work item's start.
struct PipelineAccess {
  std::uint64_t byte = 0;
  std::uint32_t bytes = 0;
  std::uint32_t issue_offset = 0;
};

struct AccessProfile : tlm::tlm_extension<AccessProfile> {
  bool write = false;
  // Either a contiguous burst of `bytes` bytes starting at byte `first_byte` ...
  std::uint64_t first_byte = 0;
  // ... or `scatter_count` accesses of `scatter_size` bytes at these byte addresses, in any
  // order (a batch's result slots) ...
  const std::uint64_t* scatter = nullptr;
  std::uint32_t scatter_size = 0;
  std::uint32_t scatter_count = 0;
  // ... or `pipeline_count` accesses an in-order pipeline issues at their offsets: a busy bank
  // delays that access and every later one (a Recursion Unit's request, one at a time, when the
  // buffer offers no TimingTarget: TimingTarget::charge_one's b_transport form).
  const PipelineAccess* pipeline = nullptr;
  std::uint32_t pipeline_count = 0;
  std::uint64_t bytes = 0;  // payload bytes moved, for traffic and energy statistics

  tlm::tlm_extension_base* clone() const override { return new AccessProfile(*this); }
  void copy_from(const tlm::tlm_extension_base& other) override { *this = static_cast<const AccessProfile&>(other); }

  // The profile of a single access `one` (which must outlive it): a one-entry pipeline.
  static AccessProfile single(const PipelineAccess& one, bool write) {
    AccessProfile a;
    a.write = write;
    a.bytes = one.bytes;
    a.pipeline = &one;
    a.pipeline_count = 1;
    return a;
  }
};

}  // namespace tigris::tlm_if
