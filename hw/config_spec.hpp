// The accelerator's keys are declared with the one configuration mechanism (config/spec.hpp),
// which the registration pipeline's configuration shares.
#pragma once

#include "config/spec.hpp"

namespace tigris::hw {

using namespace tigris::config;  // Spec, in(), one_of(), ... in every block's visit()

// Upper bounds that catch typos (a stray digit) and keep counts and products well inside int.
constexpr double kMaxUnits = 4096, kMaxEntries = 1 << 20, kMaxCycles = 1e6;

}  // namespace tigris::hw
