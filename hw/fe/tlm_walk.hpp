// The transaction-level walk of a Recursion Unit's activation (fe.recursion_unit_model "tlm",
// the default): stages FQ RS RN CD PI CL, each step's cycles from the cost table, every access
// requested when its step issues and held until the bank calendars grant it, as the RTL RU's
// ports are (rtl/). A walk engine like the RTL one: the Recursion Unit keeps the statistics of
// both from the Outcome.
#pragma once

#include <memory>

#include "walk_engine.hpp"

namespace tigris::hw {

struct AcceleratorConfig;

std::unique_ptr<WalkEngine> make_tlm_walk(const AcceleratorConfig& config);

}  // namespace tigris::hw
