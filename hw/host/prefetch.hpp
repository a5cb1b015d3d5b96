// A host speed-up, nothing the hardware does: starts loading the host cache lines of an object
// the simulator will read soon (a queued query's stack or result slot). Queries in flight
// touch megabytes between two visits, so these reads would otherwise miss every time.
#pragma once

#include <cstddef>

namespace tigris::hw {

// The first and last line of `bytes` (<= 128) bytes at `p`, to be read ...
inline void prefetch_span(const void* p, std::size_t bytes) {
  const char* c = static_cast<const char*>(p);
  __builtin_prefetch(c);
  if (bytes > 1) __builtin_prefetch(c + bytes - 1);
}
// ... or written (the line is fetched for ownership at once).
inline void prefetch_span_to_write(const void* p, std::size_t bytes) {
  const char* c = static_cast<const char*>(p);
  __builtin_prefetch(c, 1);
  if (bytes > 1) __builtin_prefetch(c + bytes - 1, 1);
}

}  // namespace tigris::hw
