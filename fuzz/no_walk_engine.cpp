// The fuzz build's configuration readers name the Recursion Unit models (hw/fe/walk_engine.cpp
// registers "tlm") but never build an accelerator, so the transaction-level walk and the model
// behind it are not compiled here: asking for the engine is a bug of the fuzz build.
#include <stdexcept>

#include "hw/fe/tlm_walk.hpp"

namespace tigris::hw {

std::unique_ptr<WalkEngine> make_tlm_walk(const AcceleratorConfig&) {
  throw std::logic_error("the fuzz build reads configurations only: it has no walk engine");
}

}  // namespace tigris::hw
