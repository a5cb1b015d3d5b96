// Where a first_leaf leader's final list is assembled while it searches (docs/model.md,
// approximate search), in the Result Buffer with its slot: radius leaders stage the in-radius
// Node Set entries their scans find; NN/kNN slots carry each entry's coordinates with its index
// (the job's slot size counts them), so a finished leader's list is its slot's Node Set entries.
// The coordinates come from an index -> entry table here: the host's shortcut for the carried
// copy, not hardware.
#pragma once

#include <cstdint>
#include <vector>

#include "hw/job.hpp"
#include "hw/tree_view.hpp"

namespace tigris::hw {

class LeaderStaging {
 public:
  // A job starts: empty stages; for NN/kNN first_leaf jobs the table of the leaf sets' entries.
  void start(const JobDescriptor& job, const TreeView& tree) {
    staged_.assign(job.approximate && job.first_leaf && job.radius() ? job.slots : 0, {});
    entry_of_.clear();
    if (!job.approximate || !job.first_leaf || job.radius() || job.num_leaves == 0) return;
    const tlm_if::PointEntry* e = tree.leaf_entries();
    const std::uint32_t n = tree.leaf_end(job.num_leaves - 1);
    std::uint32_t points = 0;
    for (std::uint32_t i = 0; i < n; ++i) points = std::max(points, (e[i].tag & tlm_if::kIndexMask) + 1);
    entry_of_.assign(points, nullptr);
    for (std::uint32_t i = 0; i < n; ++i) entry_of_[e[i].tag & tlm_if::kIndexMask] = e + i;
  }
  // Radius: the in-radius Node Set entries a leader's scans found so far (cleared when its
  // slot's query starts).
  std::vector<tlm_if::PointEntry>& staged(std::uint32_t slot) { return staged_[slot]; }
  // NN/kNN: the Node Set entry of point `index`, or nullptr (a top-tree point).
  const tlm_if::PointEntry* leaf_entry(std::uint32_t index) const {
    return index < entry_of_.size() ? entry_of_[index] : nullptr;
  }

 private:
  std::vector<std::vector<tlm_if::PointEntry>> staged_;
  std::vector<const tlm_if::PointEntry*> entry_of_;
};

}  // namespace tigris::hw
