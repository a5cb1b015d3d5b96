// What a started job looks like inside the accelerator: the CSRs decoded, the buffers' DMI
// views, and the token a query carries between the front-end and the back-end.
#pragma once

#include <cstdint>
#include <vector>

#include <systemc>

#include "sw_ref/arith.hpp"
#include "tlm/address_map.hpp"
#include "tlm/tree_image.hpp"

namespace tigris::hw {

// One entry of a query's stack in the Query Stack Buffer: a subtree still to visit and the
// squared distance to the split plane that separates it (the bypassing "distance information").
struct StackSlotEntry {
  std::uint32_t node;
  float plane2;
};

// A query in flight. It names its Query Stack Buffer / Result Buffer slot; `sp` is its stack
// depth; `leaf` the leaf set it waits for in the back-end.
struct QueryToken {
  std::uint32_t query = 0;
  std::uint32_t slot = 0;
  std::uint32_t leaf = 0;
  std::uint16_t sp = 0;
  bool started = false;
  std::uint64_t ready = 0;  // cycle the token reaches its current queue
};

// Per-query visit counts the hardware keeps for the golden check (debug counters).
struct QueryCounters {
  std::uint32_t top = 0, pruned = 0, leaf_points = 0, leaf_visits = 0;
};

struct Job {
  tlm_if::SearchMode mode = tlm_if::SearchMode::NN;
  std::uint32_t k = 1;
  float r2 = 0.0f;
  std::uint32_t num_points = 0, num_queries = 0;
  int top_height = 0;
  std::uint32_t num_top_nodes = 0;  // first leaf node id
  std::uint32_t num_leaves = 0;     // 0: no leaf sets
  std::uint32_t leaf_dir_offset = 0;
  std::uint32_t stack_entries = 1;  // per query: max(top height, 1)
  std::uint32_t slots = 0;          // queries in flight at most

  // DMI views of the buffers.
  const tlm_if::PointEntry* entries = nullptr;
  const std::uint32_t* leaf_dir = nullptr;
  const float* queries = nullptr;  // x, y, z per query
  StackSlotEntry* stacks = nullptr;
  std::uint8_t* result_slots = nullptr;
  std::uint64_t result_slot_bytes = 0;

  std::vector<QueryCounters> counters;
  // Leaf visits (query, leaf) in the order the Search Units issued them (simulated time).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> schedule;
  sc_core::sc_time period;

  Point3 query(std::uint32_t q) const { return {queries[3 * q], queries[3 * q + 1], queries[3 * q + 2]}; }
  bool leaf_nonempty(std::uint32_t leaf) const {
    return num_leaves != 0 && leaf_dir[leaf + 1] > leaf_dir[leaf];
  }
  bool node_nonempty(std::uint32_t node) const {
    return node < num_top_nodes ? entries[node].tag != tlm_if::kEmptyTag
                                : leaf_nonempty(node - num_top_nodes);
  }
  std::uint64_t cycle() const { return static_cast<std::uint64_t>(sc_core::sc_time_stamp() / period); }
};

}  // namespace tigris::hw
