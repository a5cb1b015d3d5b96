// Which model walks a Recursion Unit's activations (`fe.recursion_unit_model`): the
// transaction-level walk (tlm_walk.cpp, the default: cycles from the cost table, accesses
// granted by the bank calendars) or the RTL Recursion Unit (rtl/: Verilated, clocked cycle by
// cycle through a transactor whose grants come from the same bank calendars). The Recursion Unit
// has one code path: it hands every activation to its engine and keeps the statistics from the
// Outcome. Both read and write the same buffers through DMI, so results and visit counts must
// agree bit for bit; their cycles are the RTL cross-check (docs/validation.md).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "hw/policy_registry.hpp"

namespace tigris::tlm_if {
struct QueryRecord;
struct ResultRecord;
}  // namespace tigris::tlm_if

namespace tigris::hw {

class BankedSram;
class BufferPort;
class ResultSlots;
class TreeView;
struct JobDescriptor;
struct QueryToken;
struct StackEntry;

class WalkEngine {
 public:
  virtual ~WalkEngine() = default;

  // What an activation works on: the RU's ports and its views of their data.
  struct Ports {
    BufferPort &points, &queries, &stacks;
    const JobDescriptor& job;
    const TreeView& tree;
    const tlm_if::QueryRecord* query_records;
    StackEntry* stacks_data;
    ResultSlots& slots;
    std::vector<tlm_if::ResultRecord>& hits;  // radius hits found at top nodes
    std::uint32_t replicated_nodes;           // heap nodes below this are in the RU's own copy
    // The buffers behind points, queries and stacks when they are global buffers (else null):
    // a one-word access then takes BankedSram's inline path (BufferPort::request).
    BankedSram *points_sram, *queries_sram, *stacks_sram;
  };
  struct Outcome {
    std::uint64_t end = 0;           // the cycle the pipeline is free again (grant stalls included)
    std::uint64_t done = 0;          // the cycle its last access is complete (>= end)
    std::uint64_t grant_stalls = 0;  // cycles spent waiting for a grant
    std::uint32_t nodes = 0, pruned = 0, replica_reads = 0;
    bool finished = false;  // the stack is empty (else token.leaf is the next leaf)
  };
  // Walks `token` from cycle `now`: reads its query record, charges every access, updates the
  // token (point, sp, started, leaf), the slot (NN/kNN) or `hits` (radius).
  virtual Outcome walk(QueryToken& token, std::uint64_t now, const Ports& ports) = 0;
};

// RecursionUnitModels (hw/policy_registry.hpp): "tlm" is registered in walk_engine.cpp, linked
// whole with the policies; "rtl" by the RTL library when the build has Verilator (rtl/).

}  // namespace tigris::hw
