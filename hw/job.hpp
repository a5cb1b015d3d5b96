// A started job as the units see it: the CSRs decoded into a read-only descriptor, the
// geometry of the buffers' contents, and the token a query carries between the front-end and
// the back-end. The data itself the units reach through their own buffer ports (DMI).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "config.hpp"
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
  std::uint32_t stack_entries = 1;      // per query: max(top height, 1)
  std::uint32_t slots = 0;              // queries in flight at most
  std::uint64_t result_slot_bytes = 0;  // NN/kNN: one query's Result Buffer slot; radius: 0
  // Approximate search (docs/model.md): a query within thd of a leaf's closest leader
  // follows it. first_leaf: at the query's first leaf only, a leader's list is its final
  // results (their Node Set entries); else at every leaf, a leader's local list holds its
  // in-radius points (radius) or R best (NN/kNN) of the leaf.
  bool approximate = false;
  bool first_leaf = false;
  bool wait_for_leaders = false;  // first_leaf: a leader counts from its check; followers wait for its list
  float thd2 = 0.0f;
  std::uint32_t leader_width = 1;
  std::uint32_t leader_capacity = 0;                          // per leaf (leader.capacity_per_leaf)
  std::uint64_t leader_area_base = 0, leader_area_bytes = 0;  // Result Buffer bytes for lists

  bool radius() const { return mode == tlm_if::SearchMode::Radius; }
  std::uint64_t result_slot_address(std::uint32_t slot) const { return slot * result_slot_bytes; }
  std::uint64_t stack_base(std::uint32_t slot) const {
    return std::uint64_t{slot} * stack_entries * sizeof(StackEntry);
  }
};

constexpr std::uint32_t kNoLeaf = 0xFFFFFFFFu;

// A query in flight. It names its Query Stack Buffer / Result Buffer slot and carries its
// point (read from the Query Buffer at FQ); `sp` is its stack depth; `leaf` the leaf set it
// waits for in the back-end.
struct QueryToken {
  std::uint32_t query = 0;
  std::uint32_t slot = 0;
  std::uint32_t leaf = 0;
  std::uint16_t sp = 0;
  bool started = false;
  bool finished = false;                 // first_leaf: a follower, whose search ended in the back-end
  bool parked = false;                   // first_leaf, wait: a follower waiting with its leader (this copy is done)
  std::uint32_t first_leaf = kNoLeaf;    // first_leaf: the leaf of its Leader Check, once made
  std::uint32_t leader_entry = kNoLeaf;  // wait: a leader's entry among its first leaf's leaders
  std::uint32_t follows = kNoLeaf;       // wait: a parked follower's leader (entry at first_leaf)
  Point3 point;
  std::uint64_t ready = 0;  // cycle the token reaches its current queue
};

// first_leaf: a finished leader's record (its point and final list), sent by the Recursion
// Unit that finished it over the QDN to the SU owning its first leaf; applied at `ready`.
struct LeaderRecord {
  std::uint32_t query = 0, leaf = 0;
  std::uint32_t entry = 0;  // wait: its entry among the leaf's leaders (reserved at its check)
  Point3 point;
  std::vector<tlm_if::PointEntry> list;
  std::uint64_t ready = 0;
};

// A query's NN/kNN Result Buffer slot: the count word and k results; with approximate
// first_leaf search each result also carries its point's coordinates (12 bytes), so that a
// finished leader writes its list straight from its slot (hw/mem/leader_staging.hpp).
std::uint64_t result_slot_bytes(std::uint32_t k, bool first_leaf);

// Queries a job holds in flight at most (its Query Stack / Result Buffer slots): the smallest of
// the Query Stack slots, FQQ entries, Result Buffer slots (NN/kNN) and the query count.
std::uint64_t queries_in_flight(const AcceleratorConfig& config, int top_height, tlm_if::SearchMode mode,
                                std::uint32_t k, bool approximate, bool first_leaf, std::uint64_t num_queries);

// The one check that a job fits the configured buffers: the tree image in the Point Buffer,
// the queries in the Query Buffer, one query's stack and (NN/kNN) its k results. Returns why
// not, naming the configuration key, or an empty string.
std::string job_fit_error(const AcceleratorConfig& config, std::uint64_t image_bytes, std::uint64_t num_queries,
                          int top_height, tlm_if::SearchMode mode, std::uint32_t k, bool first_leaf = false);

}  // namespace tigris::hw
