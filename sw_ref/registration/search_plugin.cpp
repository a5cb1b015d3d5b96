#include "search_plugin.hpp"

namespace tigris::registration {

Backend parse_backend(const std::string& name) {
  if (name == "flann") return Backend::Flann;
  if (name == "exact") return Backend::Exact;
  if (name == "approx") return Backend::Approx;
  throw std::invalid_argument("unknown search back-end '" + name + "' (use flann, exact or approx)");
}

const char* to_string(Backend backend) {
  switch (backend) {
    case Backend::Flann: return "flann";
    case Backend::Exact: return "exact";
    default: return "approx";
  }
}

}  // namespace tigris::registration
