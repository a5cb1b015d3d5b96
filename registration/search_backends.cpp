#include "search_backends.hpp"

#include <stdexcept>

namespace tigris::registration {

const SearchBackend& search_backend(const std::string& search) {
  for (const SearchBackend& b : kSearchBackends)
    if (search == b.search) return b;
  std::string names;
  for (const std::string& n : search_backend_names()) names += (names.empty() ? "" : ", ") + n;
  throw std::invalid_argument("--search must be one of " + names + ", got '" + search + "'");
}

bool in_loop(const std::string& search) {
  for (const SearchBackend& b : kSearchBackends)
    if (search == b.search) return b.in_loop();
  return false;
}

std::vector<std::string> search_backend_names() {
  std::vector<std::string> names;
  for (const SearchBackend& b : kSearchBackends) names.push_back(b.search);
  return names;
}

}  // namespace tigris::registration
