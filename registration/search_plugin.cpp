#include "search_plugin.hpp"

namespace tigris::registration {

int to_pcl_results(const Neighbor* first, const Neighbor* last, const std::vector<pcl::index_t>& map,
                   pcl::Indices& k_indices, std::vector<float>& k_sqr_distances, std::vector<std::uint32_t>* local) {
  if (local) local->clear();
  for (const Neighbor* n = first; n != last; ++n) {
    k_indices.push_back(map[n->index]);
    k_sqr_distances.push_back(n->dist2);
    if (local) local->push_back(n->index);
  }
  return static_cast<int>(last - first);
}

}  // namespace tigris::registration
