#include "tree_image.hpp"

#include <cstring>
#include <stdexcept>

namespace tigris::tlm_if {

TreeImage encode_tree_image(const KdTree& tree) {
  if (tree.num_points > kIndexMask) throw std::invalid_argument("tree image: too many points");
  TreeImage img;
  img.top_height = tree.top_height;
  img.num_top_nodes = static_cast<std::uint32_t>(tree.top.size());
  std::vector<PointEntry> entries;
  entries.reserve(tree.top.size() + tree.leaf_points.size());
  for (const TopNode& n : tree.top) {
    const std::uint32_t tag = n.empty() ? kEmptyTag : (n.index | (std::uint32_t{n.axis} << kAxisShift));
    entries.push_back({n.point.x, n.point.y, n.point.z, tag});
  }
  for (std::size_t i = 0; i < tree.leaf_points.size(); ++i) {
    const Point3& p = tree.leaf_points[i];
    entries.push_back({p.x, p.y, p.z, tree.leaf_index[i]});
  }
  const std::size_t entry_bytes = entries.size() * sizeof(PointEntry);
  const bool directory = !tree.leaf_points.empty();
  img.num_leaves = directory ? tree.num_leaves() : 0;
  img.leaf_dir_offset = static_cast<std::uint32_t>(entry_bytes);
  const std::size_t dir_bytes = directory ? tree.leaf_begin.size() * sizeof(std::uint32_t) : 0;
  img.bytes.resize(entry_bytes + dir_bytes);
  std::memcpy(img.bytes.data(), entries.data(), entry_bytes);
  if (directory) std::memcpy(img.bytes.data() + entry_bytes, tree.leaf_begin.data(), dir_bytes);
  return img;
}

}  // namespace tigris::tlm_if
