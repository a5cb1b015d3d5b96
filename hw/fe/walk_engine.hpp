// Which model walks a Recursion Unit's activations (`fe.recursion_unit_model`): the
// transaction-level walk (recursion_unit.cpp: cycles from the cost table, one charge per buffer)
// or the RTL Recursion Unit (rtl/: Verilated, clocked cycle by cycle through a transactor whose
// grants come from the same bank calendars). Both read and write the same buffers through DMI,
// so results and visit counts must agree bit for bit; their cycles are the RTL cross-check
// (docs/validation.md).
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

// (Declared only: every program that reads configurations links the "tlm" registration.)
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

// RecursionUnitModels (hw/policy_registry.hpp): "tlm" makes no engine (the Recursion Unit's
// own walk; registered in walk_engine.cpp); "rtl" is registered by the RTL library when the
// build has Verilator (rtl/).

}  // namespace tigris::hw
