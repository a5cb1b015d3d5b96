// Every parameter of the accelerator model (docs/model.md), with the paper's defaults.
// Each block's visit() declares its keys' JSON names, units, allowed values and meaning
// (config/spec.hpp); the JSON configuration (config/apply.hpp, testbench/config.hpp) is built
// from them.
#pragma once

#include <cstdint>
#include <string>

#include <systemc>

#include "area_table.hpp"
#include "config_spec.hpp"
#include "cost_table.hpp"
#include "energy_table.hpp"
#include "policy_registry.hpp"
#include "sw_ref/kdtree.hpp"
#include "sw_ref/leader_policy.hpp"
#include "tlm/address_map.hpp"

namespace tigris::hw {

// How the result write-back meets the channel (docs/model.md, "Two accountings").
enum class Writeback { Channel, OffCriticalPath };
inline const char* to_string(Writeback w) { return w == Writeback::Channel ? "channel" : "off_critical_path"; }
// Where approximate search keeps the leaders' final lists.
enum class LeaderLists { Spill, Resident };
inline const char* to_string(LeaderLists l) { return l == LeaderLists::Spill ? "spill" : "resident"; }

struct SramConfig {
  std::uint64_t bytes = 0;
  int banks = 32;
  int ports = 32;
  int latency_cycles = 2;
  int word_bytes = 16;

  // `buffer` documents the bytes key: which buffer this is.
  template <class V>
  void visit(V&& v, const std::string& buffer) {
    // A buffer is one window of the host address map.
    v("bytes", bytes, {"bytes", in(1, static_cast<double>(tlm_if::kWindowSize)), buffer});
    v("banks", banks, {"banks", in(1, kMaxUnits), "word-interleaved banks, one access per bank per cycle"});
    v("ports", ports, {"accesses/cycle", in(1, kMaxUnits), "accesses accepted per cycle, all banks together"});
    v("latency_cycles", latency_cycles, {"cycles", in(0, kMaxCycles), "read latency of one access"});
    v("word_bytes", word_bytes, {"bytes", in(1, 4096), "bank interleaving granule (one entry)"});
  }
};

struct AcceleratorConfig {
  double clock_mhz = 500.0;

  struct Tree {
    int top_height = 10;
    SplitRule split_axis = SplitRule::WidestExtent;

    template <class V>
    void visit(V&& v) {
      v("top_height", top_height,
        {"levels", named(in(-1, 30), "full", -1),
         "height of the top tree the RUs walk; below it lie the leaf sets the SUs scan (-1 or "
         "\"full\": the canonical tree, Acc-KD)"});
      v("split_axis", split_axis,
        {"-", one_of({SplitRule::WidestExtent, SplitRule::RoundRobin}),
         "axis a node splits: widest extent, or x, y, z in turn"});
    }
  } tree;

  struct FrontEnd {
    int recursion_units = 64;
    bool forwarding = true;
    bool bypassing = true;
    std::uint64_t fqq_bytes = 1572864;  // 1.5 MB
    int fqq_entry_bytes = 8;
    int top_levels_replicated = 0;
    std::string recursion_unit_model = "tlm";  // a name in RecursionUnitModels (hw/fe/walk_engine.hpp)

    template <class V>
    void visit(V&& v) {
      v("recursion_units", recursion_units, {"units", in(1, kMaxUnits), "Recursion Units (RUs) in the front end"});
      v("forwarding", forwarding,
        {"-", boolean(), "PI->RS forwarding: removes the PI->RS stall (cost.ru_pi_rs_stall) per visited node"});
      v("bypassing", bypassing,
        {"-", boolean(), "a pruned node leaves the RU pipeline at RN instead of going down to PI"});
      v("fqq_bytes", fqq_bytes,
        {"bytes", at_least(1),
         "FE Query Queue: new queries and queries re-inserted by the BE; backpressure when full"});
      v("fqq_entry_bytes", fqq_entry_bytes, {"bytes", in(1, 4096), "one FQQ entry (query id + flags)"});
      v("top_levels_replicated", top_levels_replicated,
        {"levels", in(0, 16),
         "the top tree's first levels kept in every RU's own registers (2^N - 1 nodes of 16 "
         "bytes, filled by the host's tree-image write): their node reads leave the Point "
         "Buffer, whose root bank every new query otherwise reads (0: the paper's design)"});
      v("recursion_unit_model", recursion_unit_model,
        {"-", RecursionUnitModels::allowed(),
         "the model that walks every RU activation: tlm (the transaction-level walk: each step's cycles from "
         "the cost table, its accesses granted by the bank calendars) or rtl (the RTL Recursion Unit of rtl/, "
         "Verilated and clocked cycle by cycle, in builds with Verilator; identical cycles, docs/validation.md)"});
    }
  } fe;

  struct BackEnd {
    int search_units = 32;
    int pes_per_su = 32;
    int bqb_entries = 128;
    int bqb_entry_bytes = 8;            // the paper's 1 KB per SU for 128 entries
    std::string issue_policy = "mqsn";  // a name in IssuePolicies (hw/be/policies/)
    int issue_search_width = 32;

    template <class V>
    void visit(V&& v) {
      v("search_units", search_units, {"units", in(1, kMaxUnits), "Search Units (SUs) in the back end"});
      v("pes_per_su", pes_per_su, {"PEs", in(1, kMaxUnits), "PEs per SU: a 1-D query-stationary systolic array"});
      v("bqb_entries", bqb_entries, {"entries", in(1, kMaxEntries), "BE Query Buffer entries per SU"});
      v("bqb_entry_bytes", bqb_entry_bytes,
        {"bytes", in(1, 4096), "one BQB entry (query id + leaf id); sizes the BQB's area"});
      v("issue_policy", issue_policy, {"-", IssuePolicies::allowed(), IssuePolicies::doc("issue logic")});
      v("issue_search_width", issue_search_width,
        {"entries", in(1, kMaxEntries), "BQB entries the MQSN associative search checks per cycle"});
    }
  } be;

  struct Leader {
    int capacity_per_leaf = 16;
    LeaderScope scope = LeaderScope::FirstLeaf;
    LeaderInFlight in_flight = LeaderInFlight::Wait;
    int width = 0;  // every_leaf, NN/kNN: R, the nearest points a leader keeps for its followers (0: k)

    template <class V>
    void visit(V&& v) {
      v("capacity_per_leaf", capacity_per_leaf,
        {"leaders", in(0, kMaxUnits), "leaders the Leader Buffer keeps per leaf (approximate search)"});
      v("scope", scope,
        {"-", one_of({LeaderScope::FirstLeaf, LeaderScope::EveryLeaf}),
         "where approximate search checks leaders: first_leaf (the paper authors' code: a query's first "
         "leaf; a follower takes its leader's final results and stops) or every_leaf (every leaf visit, "
         "a leader's list local to the leaf)"});
      v("in_flight", in_flight,
        {"-", one_of({LeaderInFlight::Wait, LeaderInFlight::FinishedOnly}),
         "first_leaf: what a Leader Check sees of leaders still searching: wait (a leader counts from its "
         "check; its followers park until its final list is written) or finished_only (a leader counts "
         "once its record has reached the Leader Buffer)"});
      v("width", width,
        {"points", in(0, kMaxUnits),
         "every_leaf, NN/kNN: R, the nearest points of the leaf a leader keeps for its followers (0: k; "
         "--leader-width)"});
    }
  } leader;

  struct NodeCache {
    std::uint64_t bytes = 131072;  // 128 KB
    std::string policy = "lru";    // a name in ReplacementPolicies (hw/be/policies/)

    template <class V>
    void visit(V&& v) {
      v("bytes", bytes, {"bytes", at_least(0), "Node Cache: whole Node Sets, read as FIFOs; 0 turns it off"});
      v("policy", policy, {"-", ReplacementPolicies::allowed(), ReplacementPolicies::doc("Node Set to evict")});
    }
  } node_cache;

  struct Sram {
    // Banks are sized to the requesters, so that the paper's one node per cycle per RU can be
    // fed (the paper gives capacities, not banking): the Point Buffer serves 64 RU node reads and
    // 32 SU Node Set streams a cycle (128 banks); the Query Stack and Result Buffers one access a
    // cycle per RU (64 banks); the Query Buffer one read per RU activation (8 banks).
    // Points: 16-byte entries (x, y, z, index): the (dist2, index) order needs the index next
    // to each point, so 2 MiB holds the paper's ~130k points (its 1.5 MB assumed 12 bytes).
    SramConfig points{2097152, 128, 128, 2, 16};
    SramConfig queries{1572864, 8, 8, 2, 12};       // 1.5 MB
    SramConfig query_stack{1258291, 64, 64, 2, 8};  // 1.2 MB
    SramConfig results{3145728, 64, 64, 2, 8};      // 3 MB

    template <class V>
    void visit(V&& v) {
      points.visit(in_block(v, "points"), "Point Buffer: the tree's points, 16-byte entries (x, y, z, index)");
      queries.visit(in_block(v, "queries"), "Query Buffer: the queries");
      query_stack.visit(in_block(v, "query_stack"), "Query Stack Buffer: top-height entries per query in flight");
      results.visit(in_block(v, "results"), "Result Buffer, double-buffered to DRAM");
    }
  } sram;

  struct ResultBuffer {
    double slot_fraction = 0.5;
    double leader_fraction = 0.25;
    LeaderLists leader_lists = LeaderLists::Spill;

    template <class V>
    void visit(V&& v) {
      v("slot_fraction", slot_fraction,
        {"-", above(0, 1),
         "share of the Result Buffer (sram.results.bytes) that may hold NN/kNN query slots (one "
         "per query in flight); what the slots leave double-buffers the result stream to DRAM"});
      v("leader_fraction", leader_fraction,
        {"-", above(0, 1),
         "approximate search: share of the Result Buffer holding the leaders' local result "
         "lists, split evenly among the SUs; a list that finds its SU's share full is kept in "
         "DRAM (read and written over the write-back channel) unless leader_lists is resident"});
      v("leader_lists", leader_lists,
        {"-", one_of({LeaderLists::Spill, LeaderLists::Resident}),
         "approximate search: where a leader's final list lives once its SU's share "
         "(leader_fraction) is full: spill (the physical machine: kept in DRAM, over the write-back "
         "channel at DRAM energy) or resident (the paper's accounting: followers \"fetch search nodes "
         "from the Result Buffer\", so every list stays in the Result Buffer, read and written at its "
         "banks and price; the paper bounds the lists by nothing)"});
    }
  } result_buffer;

  struct Dram {
    double bytes_per_cycle = 51.2;  // one DDR4-3200 x64 channel (25.6 GB/s) at 500 MHz
    int latency_cycles = 100;
    Writeback writeback = Writeback::Channel;

    template <class V>
    void visit(V&& v) {
      v("bytes_per_cycle", bytes_per_cycle,
        {"bytes/cycle", in(1e-3, 1e6),
         "DRAM bandwidth for the result write-back (at least 1e-3: below it a job's cycle "
         "count leaves the 64-bit range)"});
      v("latency_cycles", latency_cycles, {"cycles", in(0, kMaxCycles), "DRAM access latency"});
      v("writeback", writeback,
        {"-", one_of({Writeback::Channel, Writeback::OffCriticalPath}),
         "how the result stream meets DRAM: channel (the physical machine: the double-buffered stream "
         "area drains at bytes_per_cycle, a writer waits while both halves are full, the job ends when "
         "the last byte is in DRAM) or off_critical_path (the paper's accounting: the double buffer "
         "\"take[s] the result write traffic off the critical path\": a record is accepted as it is "
         "written and the job ends with its last record; the bytes are still counted, and leader lists "
         "kept in DRAM still wait for their transfers)"});
    }
  } dram;

  // The host link a job's tree image and queries cross to the accelerator, and its results
  // back (tigris run --trace: each transfer modeled as latency + bytes / bandwidth, apart from
  // the simulated search; no energy).
  struct Host {
    double link_gb_per_s = 15.75;  // PCIe 3.0 x16: 8 GT/s x 16 lanes x 128b/130b = 15.75 GB/s
    double link_latency_us = 1.0;  // per transfer: a PCIe DMA round trip is about 1 us

    template <class V>
    void visit(V&& v) {
      v("link_gb_per_s", link_gb_per_s,
        {"GB/s", in(1e-3, 1e6),
         "host link bandwidth for loading a job (tree image, queries) and reading its results: "
         "PCIe 3.0 x16, 8 GT/s x 16 lanes x 128b/130b = 15.75 GB/s (an AXI4 port of 128 bits at "
         "500 MHz would be 8 GB/s)"});
      v("link_latency_us", link_latency_us,
        {"us", in(0, 1e6), "host link latency per transfer (a PCIe DMA round trip, about 1 us)"});
    }
  } host;

  struct Stall {
    double rate = 0.0;
    std::uint64_t seed = 1;

    template <class V>
    void visit(V&& v) {
      v("rate", rate,
        {"-", in(0, 0.9),
         "random stall injection: probability that a hand-off (FQQ -> RU, RU -> QDN, QDN -> "
         "BQB, SU -> FE, SRAM and write-back grants) is held back a cycle, and again for each "
         "further cycle; results must not change (0: off)"});
      v("seed", seed, {"-", at_least(0), "random stall injection: the seed of every injection point's stream"});
    }
  } stall;

  // How the simulator runs a job, not hardware: sampled simulation (docs/sampling.md). A
  // sampled job simulates its fill, `windows` stretches of consecutive queries spread over the
  // job and its drain in one stream, and estimates the rest from the windows' throughput.
  struct Sim {
    static constexpr int kAuto = -1;
    double sampling = 0.0;  // 0: off (every query simulated); kAuto; else the share simulated
    int windows = 20;
    int warm_queries = kAuto;
    int window_queries = kAuto;

    template <class V>
    void visit(V&& v) {
      v("sampling", sampling,
        {"-", named(named(in(0, 1), "off", 0), "auto", kAuto),
         "sampled simulation: off (every query simulated in detail), auto (the job is sampled when it is long "
         "enough for its windows to be estimated well, else simulated in full) or the share of the queries to "
         "simulate (0 < f <= 1); the others take the golden model's results and their cycles and energy are "
         "estimated, with a 95% confidence interval"});
      v("windows", windows,
        {"windows", in(2, 1000), "sampled simulation: stretches of consecutive queries measured in detail"});
      v("warm_queries", warm_queries,
        {"queries", named(in(0, 1 << 30), "auto", kAuto),
         "sampled simulation: queries simulated in detail before each window and not measured, so that the "
         "window sees a full machine (auto: as many as the job holds in flight)"});
      v("window_queries", window_queries,
        {"queries", named(in(1, 1 << 30), "auto", kAuto),
         "sampled simulation with sim.sampling = auto: queries measured per window (auto: as many as the job "
         "holds in flight); a share given in sim.sampling sets it instead"});
    }
  } sim;

  CostTable cost;
  EnergyTable energy;
  AreaTable area;

  // Every key, in the order the reference and the dump list them (config/key_table.hpp).
  static constexpr const char* kListCommand = "tigris run --list-config";
  static constexpr const char* kSetExample = "fe.recursion_units=32";
  template <class V>
  void visit(V&& v) {
    v("clock_mhz", clock_mhz,
      {"MHz", in(1, 1e5),
       "accelerator clock (1 MHz .. 100 GHz: SystemC's 64-bit picosecond time must hold every "
       "job's cycles)"});
    tree.visit(in_block(v, "tree"));
    fe.visit(in_block(v, "fe"));
    be.visit(in_block(v, "be"));
    leader.visit(in_block(v, "leader"));
    node_cache.visit(in_block(v, "node_cache"));
    sram.visit(in_block(v, "sram"));
    result_buffer.visit(in_block(v, "result_buffer"));
    dram.visit(in_block(v, "dram"));
    host.visit(in_block(v, "host"));
    stall.visit(in_block(v, "stall"));
    sim.visit(in_block(v, "sim"));
    cost.visit(in_block(v, "cost"));
    energy.visit(in_block(v, "energy"));
    area.visit(in_block(v, "area"));
  }

  sc_core::sc_time period() const { return sc_core::sc_time(1000.0 / clock_mhz, sc_core::SC_NS); }
};

}  // namespace tigris::hw
