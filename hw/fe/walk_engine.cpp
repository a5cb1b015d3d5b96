// The "tlm" model of fe.recursion_unit_model: the transaction-level walk (tlm_walk.cpp). In a
// file of its own, linked whole with the policies (hw/CMakeLists.txt), so that every program
// that reads configurations registers it.
#include "walk_engine.hpp"

#include "tlm_walk.hpp"

namespace tigris::hw {
namespace {

const bool registered = RecursionUnitModels::add(
    "tlm", "transaction level: each step's cycles from the cost table, its accesses granted by the bank calendars",
    make_tlm_walk);

}  // namespace

}  // namespace tigris::hw
