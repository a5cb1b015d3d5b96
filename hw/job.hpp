// A started job as the units see it: the CSRs decoded into a read-only descriptor, the
// geometry of the buffers' contents, and the token a query carries between the front-end and
// the back-end. The data itself the units reach through their own buffer ports (DMI).
#pragma once

#include <cstdint>
#include <string>

#include "hw/config.hpp"
#include "sw_ref/arith.hpp"
#include "tlm/address_map.hpp"
#include "tlm/tree_image.hpp"

namespace tigris::hw {

// One entry of a query's stack in the Query Stack Buffer: a subtree still to visit and the
// squared distance to the split plane that separates it (the bypassing "distance information").
struct StackEntry {
  std::uint32_t node;
  float plane2;
};
static_assert(sizeof(StackEntry) == 8, "stack entries are 8 bytes");

// The decoded CSRs and what follows from them; fixed from START to done.
struct JobDescriptor {
  tlm_if::SearchMode mode = tlm_if::SearchMode::NN;
  std::uint32_t k = 1;
  float r2 = 0.0f;
  std::uint32_t num_queries = 0;
  int top_height = 0;
  std::uint32_t num_top_nodes = 0;  // first leaf node id
  std::uint32_t num_leaves = 0;     // 0: no leaf sets
  std::uint32_t leaf_dir_offset = 0;
  std::uint32_t stack_entries = 1;  // per query: max(top height, 1)
  std::uint32_t slots = 0;          // queries in flight at most
  std::uint64_t result_slot_bytes = 0;  // NN/kNN: one query's Result Buffer slot; radius: 0
  // Approximate search (docs/model.md): a query within thd of a leaf's closest leader
  // follows it; a leader's local list holds its in-radius points (radius) or R best (NN/kNN).
  bool approximate = false;
  float thd2 = 0.0f;
  std::uint32_t leader_width = 1;
  std::uint32_t leader_capacity = 0;  // per leaf (leader.capacity_per_leaf)
  std::uint64_t leader_area_base = 0, leader_area_bytes = 0;  // Result Buffer bytes for lists

  bool radius() const { return mode == tlm_if::SearchMode::Radius; }
  std::uint64_t result_slot_address(std::uint32_t slot) const { return slot * result_slot_bytes; }
  std::uint64_t stack_base(std::uint32_t slot) const {
    return std::uint64_t{slot} * stack_entries * sizeof(StackEntry);
  }
};

// A query in flight. It names its Query Stack Buffer / Result Buffer slot and carries its
// point (read from the Query Buffer at FQ); `sp` is its stack depth; `leaf` the leaf set it
// waits for in the back-end.
struct QueryToken {
  std::uint32_t query = 0;
  std::uint32_t slot = 0;
  std::uint32_t leaf = 0;
  std::uint16_t sp = 0;
  bool started = false;
  Point3 point;
  std::uint64_t ready = 0;  // cycle the token reaches its current queue
};

// The one check that a job fits the configured buffers: the tree image in the Point Buffer,
// the queries in the Query Buffer, one query's stack and (NN/kNN) its k results. Returns why
// not, naming the configuration key, or an empty string.
std::string job_fit_error(const AcceleratorConfig& config, std::uint64_t image_bytes,
                          std::uint64_t num_queries, int top_height, tlm_if::SearchMode mode,
                          std::uint32_t k);

}  // namespace tigris::hw
