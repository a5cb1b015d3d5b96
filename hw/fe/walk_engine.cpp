// The "tlm" model of fe.recursion_unit_model: no engine, the Recursion Unit's own walk. In a
// file of its own, linked whole with the policies (hw/CMakeLists.txt), so that every program
// that reads configurations registers it.
#include "walk_engine.hpp"

namespace tigris::hw {
namespace {

const bool registered = RecursionUnitModels::add(
    "tlm", "transaction level: each step's cycles from the cost table, its accesses granted by the bank calendars",
    [](const AcceleratorConfig&) { return std::unique_ptr<WalkEngine>(); });

}  // namespace

}  // namespace tigris::hw
