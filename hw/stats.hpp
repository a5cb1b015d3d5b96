// Counters every unit keeps; the testbench turns them into the stats JSON (DESIGN.md sec. 8).
#pragma once

#include <cstdint>

namespace tigris::hw {

struct BufferStats {
  std::uint64_t reads = 0, writes = 0;            // word accesses
  std::uint64_t read_bytes = 0, write_bytes = 0;  // payload bytes
  std::uint64_t conflict_cycles = 0;              // cycles lost to busy banks or ports
};

struct RecursionUnitStats {
  std::uint64_t activations = 0;       // queries taken from the FQQ
  std::uint64_t busy_cycles = 0;       // pipeline cycles (FQ, nodes, stalls inside the walk)
  std::uint64_t pi_rs_stall_cycles = 0;  // of busy: PI->RS dependency (no forwarding)
  std::uint64_t prune_cycles = 0;      // of busy: pruned nodes
  std::uint64_t sram_stall_cycles = 0; // waiting for buffer banks beyond the pipeline time
  std::uint64_t bqb_full_stall_cycles = 0;  // holding a query the BE Query Buffer cannot take
  std::uint64_t writeback_stall_cycles = 0; // results waiting for the write-back stream
  std::uint64_t nodes = 0, pruned = 0;
};

struct SearchUnitStats {
  std::uint64_t batches = 0;            // Node Set streams through the PE array
  std::uint64_t queries = 0;            // query-leaf visits served
  std::uint64_t busy_cycles = 0;        // PE array streaming (fill, stream, drain)
  std::uint64_t issue_cycles = 0;       // associative search + issue
  std::uint64_t sram_stall_cycles = 0;  // streaming slowed by Point/Result Buffer banks
  std::uint64_t writeback_stall_cycles = 0;  // radius hits waiting for the write-back stream
  std::uint64_t pe_busy_cycles = 0;     // sum over PEs of cycles holding a query
  std::uint64_t bqb_max_occupancy = 0;
};

struct NodeCacheStats {
  std::uint64_t hits = 0, misses = 0, read_bytes = 0, fill_bytes = 0;
};

struct QdnStats {
  std::uint64_t queries = 0;
  std::uint64_t port_wait_cycles = 0;  // a query waited for its SU port
};

}  // namespace tigris::hw
