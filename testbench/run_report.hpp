// The stats JSON of `tigris run` (DESIGN.md sections 8 and 10) from the accelerator's counters.
#pragma once

#include <nlohmann/json.hpp>

#include "hw/top.hpp"

namespace tigris {

// `units`, `buffers`, `energy_pj` and the lower bound, from a finished accelerator.
nlohmann::json units_json(const hw::TigrisAccelerator& accel, std::uint64_t cycles);
nlohmann::json buffers_json(const hw::TigrisAccelerator& accel);
nlohmann::json energy_json(const hw::TigrisAccelerator& accel);
// max(top visits / #RU, leaf-point visits / (#SU x #PE)): cycles no schedule can beat.
double lower_bound_cycles(const hw::TigrisAccelerator& accel);

}  // namespace tigris
