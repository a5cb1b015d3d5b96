// Every parameter of the accelerator model (DESIGN.md section 6), with the paper's defaults.
// The JSON configuration (testbench/config.*) maps dotted keys onto these fields one to one.
#pragma once

#include <cstdint>
#include <string>

#include <systemc>

#include "cost_table.hpp"
#include "energy_table.hpp"
#include "sw_ref/kdtree.hpp"

namespace tigris::hw {

// The Search Unit issue logic (be.issue_policy).
enum class IssuePolicyKind { Mqsn, Mqmn };
inline const char* to_string(IssuePolicyKind k) { return k == IssuePolicyKind::Mqsn ? "mqsn" : "mqmn"; }

struct SramConfig {
  std::uint64_t bytes = 0;
  int banks = 32;             // word-interleaved banks, one access per bank per cycle
  int ports = 32;             // accesses the buffer accepts per cycle, all banks together
  int latency_cycles = 2;     // read latency of one access
  int word_bytes = 16;        // bank interleaving granule (one point entry)
};

struct AcceleratorConfig {
  double clock_mhz = 500.0;

  struct Tree {
    int top_height = 10;                // -1: full height (canonical tree, Acc-KD)
    SplitRule split_axis = SplitRule::WidestExtent;  // widest | round-robin
  } tree;

  struct FrontEnd {
    int recursion_units = 64;
    bool forwarding = true;
    bool bypassing = true;
    std::uint64_t fqq_bytes = 1572864;  // FE Query Queue: 1.5 MB
    int fqq_entry_bytes = 8;            // query id + flags
  } fe;

  struct BackEnd {
    int search_units = 32;
    int pes_per_su = 32;
    int bqb_entries = 128;              // BE Query Buffer per SU
    IssuePolicyKind issue_policy = IssuePolicyKind::Mqsn;
    int issue_search_width = 32;        // BQB entries the associative search checks per cycle
  } be;

  struct Leader {
    int capacity_per_leaf = 16;
  } leader;

  struct NodeCache {
    std::uint64_t bytes = 131072;  // 128 KB; 0 turns the cache off
  } node_cache;

  struct Sram {
    // Banks are sized to the requesters, so that the paper's one node per cycle per RU can be
    // fed (the paper gives capacities, not banking): the Point Buffer serves 64 RU node reads and
    // 32 SU Node Set streams a cycle (128 banks); the Query Stack and Result Buffers one access a
    // cycle per RU (64 banks); the Query Buffer one read per RU activation (8 banks).
    // Points: 16-byte entries (x, y, z, index): the (dist2, index) order needs the index next
    // to each point, so 2 MiB holds the paper's ~130k points (its 1.5 MB assumed 12 bytes).
    SramConfig points{2097152, 128, 128, 2, 16};
    SramConfig queries{1572864, 8, 8, 2, 12};        // 1.5 MB of 12-byte queries
    SramConfig query_stack{1258291, 64, 64, 2, 8};   // 1.2 MB; `top height` 8-byte entries a query
    SramConfig results{3145728, 64, 64, 2, 8};       // 3 MB, double-buffered to DRAM
  } sram;

  struct ResultBuffer {
    double slot_fraction = 0.5;  // share of sram.results.bytes holding NN/kNN query slots
  } result_buffer;

  struct Dram {
    double bytes_per_cycle = 51.2;  // result write-back: one DDR4-3200 x64 channel (25.6 GB/s) at 500 MHz
    int latency_cycles = 100;
  } dram;

  CostTable cost;
  EnergyTable energy;

  sc_core::sc_time period() const { return sc_core::sc_time(1000.0 / clock_mhz, sc_core::SC_NS); }
};

}  // namespace tigris::hw
