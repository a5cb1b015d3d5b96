// Timing-only buffer accesses. Units read and write buffer contents through DMI (function
// only); each work item then sends ONE TLM_IGNORE_COMMAND transaction per buffer carrying this
// extension, and the buffer adds the cycles its banks, ports and latency cost to the annotated
// delay (DESIGN.md section 7: never one b_transport per point).
#pragma once

#include <cstdint>

#include <tlm>

namespace tigris::tlm_if {

struct AccessProfile : tlm::tlm_extension<AccessProfile> {
  bool write = false;
  // Either a contiguous burst of `words` bank words starting at byte `first_byte` ...
  std::uint64_t first_byte = 0;
  std::uint32_t words = 0;
  // ... or `scatter_count` single-word accesses at these byte addresses.
  const std::uint64_t* scatter = nullptr;
  std::uint32_t scatter_count = 0;
  // With scatter: the cycle (after the start) at which an in-order pipeline issues each access;
  // a busy bank then delays that access and every later one (the pipeline stalls).
  const std::uint32_t* issue_offset = nullptr;
  std::uint64_t bytes = 0;  // payload bytes moved, for traffic and energy statistics

  tlm::tlm_extension_base* clone() const override { return new AccessProfile(*this); }
  void copy_from(const tlm::tlm_extension_base& other) override {
    *this = static_cast<const AccessProfile&>(other);
  }
};

}  // namespace tigris::tlm_if
