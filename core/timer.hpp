// Wall time of a phase, measured one way everywhere: seconds since a steady-clock instant.
#pragma once

#include <chrono>

namespace tigris {

using SteadyClock = std::chrono::steady_clock;

inline double seconds_since(SteadyClock::time_point t0) {
  return std::chrono::duration<double>(SteadyClock::now() - t0).count();
}

}  // namespace tigris
