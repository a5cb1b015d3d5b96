// The one cost table of the timing model (docs/model.md, timing): every cycle count a unit
// charges comes from here, so a reader can see the whole timing model at a glance (visit()
// documents each entry: the `cost.` keys).
#pragma once

#include "config_spec.hpp"

namespace tigris::hw {

struct CostTable {
  // Recursion Unit, stages FQ RS RN CD PI CL (paper Fig. 8).
  int ru_fetch_query = 1;
  int ru_node = 1;
  int ru_pi_rs_stall = 3;
  int ru_prune_at_rn = 2;
  int ru_prune_no_bypass = 4;
  int ru_drain = 2;
  // Query Distribution Network.
  int qdn_latency = 1;
  int qdn_port_interval = 1;
  // Search Unit.
  int pe_pipeline_depth = 3;  // paper Fig. 9
  int node_cache_hit = 0;
  int leader_check = 1;
  int issue_cycle = 1;
  int result_writeback = 1;
  int be_to_fe = 1;
  // Host interface (outside the job's cycles: loading before START, reading after done).
  int host_csr_access = 1;
  int host_link_bytes_per_cycle = 32;

  template <class V>
  void visit(V&& v) {
    const auto cycles = [&](const char* name, int& field, const char* doc) {
      v(name, field, {"cycles", in(0, kMaxCycles), doc});
    };
    cycles("ru_fetch_query", ru_fetch_query, "RU stage FQ: once per activation (a query taken from the FQQ)");
    v("ru_node", ru_node, {"cycles", in(1, kMaxCycles), "RU: one node through RS..PI when nothing stalls"});
    cycles("ru_pi_rs_stall", ru_pi_rs_stall, "RU: PI->RS dependency stall per visited node without forwarding");
    cycles("ru_prune_at_rn", ru_prune_at_rn, "RU: a pruned node with bypassing (leaves at RN)");
    cycles("ru_prune_no_bypass", ru_prune_no_bypass, "RU: a pruned node without bypassing (RS..PI)");
    cycles("ru_drain", ru_drain, "RU: CD..CL behind the last node before the query is sent on");
    cycles("qdn_latency", qdn_latency, "QDN: FE -> BQB wire and arbitration");
    cycles("qdn_port_interval", qdn_port_interval, "QDN: interval between two queries on one SU port");
    cycles("pe_pipeline_depth", pe_pipeline_depth, "PE pipeline: read, distance, insert");
    cycles("node_cache_hit", node_cache_hit,
           "SU: a Node Set streamed from the Node Cache, cycles before its first word");
    cycles("leader_check", leader_check,
           "SU Leader Check: picking the closest leader and comparing with thd^2, after the "
           "leaf's leaders streamed past the batch's PEs (one per cycle, like Node Set points)");
    cycles("issue_cycle", issue_cycle, "SU issue logic per batch beyond the associative search");
    cycles("result_writeback", result_writeback, "a finished query's results leave the RU (after its last walk)");
    cycles("be_to_fe", be_to_fe, "a scanned query re-enters the FQQ");
    cycles("host_csr_access", host_csr_access, "host: one CSR read or write");
    v("host_link_bytes_per_cycle", host_link_bytes_per_cycle,
      {"bytes/cycle", in(1, kMaxCycles), "host: reading the result region from DRAM"});
  }
};

}  // namespace tigris::hw
