#include "search_settings.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tigris::registration {

void SearchSettings::validate_injection() const {
  if (inject_kth < 1)
    throw std::invalid_argument("search plug-in: inject_kth must be >= 1 (1: the nearest, no error), got " +
                                std::to_string(inject_kth));
  if (shell_inner == 0.0f && shell_outer == 0.0f) return;
  if (!std::isfinite(shell_inner) || !std::isfinite(shell_outer) || shell_inner < 0.0f || !(shell_inner < shell_outer))
    throw std::invalid_argument("search plug-in: the injected shell needs 0 <= shell_inner < shell_outer, got " +
                                std::to_string(shell_inner) + ", " + std::to_string(shell_outer));
}

int SearchSettings::height_for(std::size_t points) const {
  if (leaf_size <= 0) return top_height;
  int h = 0;
  for (std::size_t n = points; n > static_cast<std::size_t>(leaf_size); n /= 2) ++h;
  return h;
}

SearchParams golden_params(SearchParams p, const SearchSettings& s) {
  if (s.backend != Backend::Approx) return p;
  p.approximate = true;
  p.approx_thd = p.mode == Mode::Radius ? s.radius_thd * p.radius : s.nn_thd;
  p.leader_capacity = s.leader_capacity;
  p.leader_width = s.leader_width;
  p.leader_scope = s.leader_scope;
  p.leader_in_flight = s.leader_in_flight;
  return p;
}

}  // namespace tigris::registration
