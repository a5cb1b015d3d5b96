#include "search_plugin.hpp"

namespace tigris::registration {

void SearchSettings::validate_injection() const {
  if (inject_kth < 1)
    throw std::invalid_argument("search plug-in: inject_kth must be >= 1 (1: the nearest, no error), got " +
                                std::to_string(inject_kth));
  if (shell_inner == 0.0f && shell_outer == 0.0f) return;
  if (!std::isfinite(shell_inner) || !std::isfinite(shell_outer) || shell_inner < 0.0f ||
      !(shell_inner < shell_outer))
    throw std::invalid_argument("search plug-in: the injected shell needs 0 <= shell_inner < shell_outer, got " +
                                std::to_string(shell_inner) + ", " + std::to_string(shell_outer));
}

}  // namespace tigris::registration
